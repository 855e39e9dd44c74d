"""The compiled plan's loop rewritten so that the compiler can vectorise it (SIMD).

The compiled plan (`excavkin.kinematics.compiled`) is one scalar loop over samples. Its
arrays are strided views of any layout and it stores a hundred rows that the compiler cannot
prove apart, and its statuses are set in branches: so the compiler keeps it scalar, one sample
at a time. Here the same statements are rewritten, mechanically, to run over blocks of
`WIDTH` samples held in one contiguous scratch array:

- every array the loop reads (inputs, constants, statuses) is copied into a row of the scratch,
  and every array it writes is a row of it, copied out to the result after the block; each
  row is at a constant offset in the source, so the rows are provably apart;
- every ``if`` becomes selects: a name assigned under a condition takes
  ``value if condition else name``, ``and``/``or`` of conditions become ``&``/``|``.

So the block's loop is straight-line arithmetic over one array, which LLVM vectorises (with
the loop's own arctangent, `excavkin.kinematics.fast_atan2`, and no libm call but the
rotations' sine and cosine). The arithmetic, its order and every status are the scalar loop's:
the two give the same numbers to the bit (tested), and the scalar source stays the one that
the sensitivities differentiate.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import re
from pathlib import Path

from excavkin.kinematics.one_at_a_time import one_at_a_time

#: samples a block: its scratch (a few hundred rows at most) stays in the core's L2 cache
WIDTH = 256

#: the streaming stores' source, hashed into each kernel's text: numba's cache of a kernel
#: is keyed by the kernel's own file, and an intrinsic is compiled into it
_STREAMING = hashlib.sha256(Path(__file__).with_name("streaming.py").read_bytes()).hexdigest()[:16]

#: the arrays the scalar loop reads per sample, and those it writes
_READ = {"q", "qd", "qdd", "K", "status", "failed"}
_WRITTEN = {"x", "v", "a", "trans", "body", "element", "status", "failed", "near", "near_step"}


_HEAD = """
# the inputs and constants: the chunk's samples, arrays of any layout, read only; the outputs:
# the whole solve's arrays (C order, so that a row's samples are provably contiguous), the
# chunk's samples from s0 on
R2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
A1, A2, A3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
SIGNATURE = numba.void(
    R2, R2, R2, R2, numba.int64, A3, A3, A3, A2, A3, A3, numba.int8[::1], numba.int16[::1],
    numba.float64, numba.float64, A1, numba.int16[::1], numba.int64,
)


@numba.njit(SIGNATURE, nogil=True, cache=True, error_model="numpy")
def kernel(q, qd, qdd, K, ks, x, v, a, trans, body, element, status, failed, close_tol,
           singular_tol, near, near_step, s0):
    nan = math.nan
"""


@functools.lru_cache(maxsize=64)
@one_at_a_time
def vectorised(text: str, per_sample: bool, by_design: bool = False, keep: bool = False) -> str:
    """The compiled plan's source ``text`` (its loop over samples) rewritten over blocks of
    `WIDTH` samples in a contiguous scratch, branch-free. The kernel's inputs (``q``,
    ``qd``, ``qdd``, ``K``) are a chunk's samples; its outputs are the whole solve's arrays,
    the chunk's samples starting at its argument ``s0``. ``per_sample``: the constants
    table has a column per sample (a family of designs), else one column, whose values are
    read once, before the loop. ``by_design``: the table has a column per design, each
    design's ``ks`` poses one after another (a study's samples, design-major): sample ``i``
    of the chunk reads column ``(r0_ + i) // ks``, ``r0_`` the kernel's last argument (the
    chunk's first sample's pose), so that a design's constants are made once, not copied
    to each of its poses. ``keep``: ``by_design``'s arguments (the rows kept, the far
    samples' tops) and their use, with the constants as ``per_sample`` reads them (one
    design's hoisted, or a column a sample: its poses argument the stride, 0 or 1; its first
    pose unread): a solve of some columns (`excavkin.kinematics.solve.solve_selected`)."""
    keep = keep or by_design
    per_sample = per_sample or by_design
    tree = ast.parse(text)
    fn = next(f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "kernel")
    loop = next(s for s in fn.body if isinstance(s, ast.For))
    prelude = text[: text.index("\n# one signature")]
    r = _Rewriter(per_sample)
    body: list[str] = []
    for st in loop.body:
        if isinstance(st, ast.Assign) and _name(st.targets[0]) == "j":
            continue  # the constants' column: read in the copy-in loop
        r.statement(st, None, body)
    reads, writes = _tables(r.reads), _tables(r.writes)
    imports = "import math\n\nimport numpy as np\n"
    stores = f"from excavkin.kinematics.streaming import fence, stream  # {_STREAMING}\n"
    prelude = prelude.replace("import math\n", imports, 1)
    prelude = _inlined_straight(prelude).replace("import numba\n", "import numba\n" + stores, 1)
    out = [prelude.replace("\n\n@numba.njit(", _SELECT + "\n@numba.njit(", 1), ""]
    # each array's rows: its indices before the sample's, and the scratch row (constants)
    tables = {**reads, **writes}  # (status and failed are both: one row each)
    out += [f"T_{name} = np.array({rows!r}, dtype=np.int64)" for name, rows in tables.items()]
    head = _HEAD.rstrip("\n")
    if keep:  # the chunk's first sample's pose, the rows kept, the far samples' tops
        head = head.replace(
            "numba.int64,\n)",
            "numba.int64, numba.int64,\n    numba.int8[::1], numba.int64[::1], numba.float64,\n)",
        )
        head = head.replace("near_step, s0):", "near_step, s0, r0_, keep, tops, near_at):")
    passes, spilled = in_passes(straight_line(body), len(r.rows))
    n_rows = len(r.rows) + spilled["f"]
    hoisted = [f"    {name} = K[{c}, 0]" for name, c in r.hoisted.items()]
    first = [  # the block's inputs into the scratch
        *(["        for l_ in range(nb_):", "            J_[l_] = (r0_ + b0_ + l_) // ks"]
          if by_design else []),
        *(line for name, rows in reads.items()
          for line in _copy(name, rows, into_scratch=True, by_design=by_design, keep=keep)),
    ]  # fmt: skip
    last = [  # its outputs out of it
        *(_tops(r.rows["status[i]"], r.rows["near[i]"], len(r.rows)) if keep else []),
        *(line for name, rows in writes.items()
          for line in _copy(name, rows, into_scratch=False, by_design=by_design, keep=keep)),
    ]  # fmt: skip
    kinds = f"    KIND_ = np.array({_kinds(writes, len(r.rows))!r}, dtype=np.int64)"
    if len(passes) >= SPLIT_PASSES:  # a kernel of its own for each pass, one after another
        study = kinds if keep else None
        # each later pass copies the inputs into their rows again (the same values): a pass's
        # loop is vectorised only behind a loop that stores into the scratch (`_split`)
        again = _copy("q", reads["q"], into_scratch=True) if "q" in reads else []
        out += _split(
            head, passes, (first, again), last, hoisted, n_rows, spilled, per_sample, study,
            by_design,
        )  # fmt: skip
        return "\n".join(_own_indices(out)) + "\n"
    out += [
        head,
        *([] if per_sample else _ONE_DESIGN),
        *hoisted,
        f"    S_ = np.empty({n_rows * WIDTH})",
        *(
            f"    {_SPILL[t]} = np.empty({spilled[t] * WIDTH}, dtype=np.{_DTYPE[t]})"
            for t in "ib"
            if spilled[t]
        ),
        "    n_ = q.shape[1]",
        f"    for b0_ in range(0, n_, {WIDTH}):",
        f"        nb_ = min({WIDTH}, n_ - b0_)",
    ]
    if keep:  # each sample's design (a study's), the far samples' mask, the rows' kinds
        out[-3:-3] = [*(_BY_DESIGN[:1] if by_design else []), *_BY_DESIGN[1:], kinds]
    out += [*first, *(line for lines in passes for line in lines), *last]
    out.append("    fence()")
    return "\n".join(_own_indices(out)) + "\n"


def _own_indices(lines: list[str]) -> list[str]:
    """Each loop of the kernel with names of its own, numbered by the loop's line: its index
    (``l_`` → ``l40_``, ``k_`` → ``k38_`` …) and a copy loop's row (``row_``). A name
    assigned in several loops is one that numba's SSA pass renames itself, walking every
    statement of the kernel once for each such name: the loops over a block's samples and the
    copies share their names, and a large plan's kernel has tens of thousands of statements."""
    out: list[str] = []
    scopes: list[tuple[int, dict[str, str]]] = []  # (a loop's indent, its renames)
    for line in lines:
        indent = len(line) - len(line.lstrip())
        while scopes and line.strip() and indent <= scopes[-1][0]:
            scopes.pop()
        renames = {k: v for _, names in scopes for k, v in names.items()}
        head = _LOOP.match(line)
        if head is not None and head["index"] in _OWN:  # its header binds the new names
            count = len(out) + 1  # (a line's number: unique)
            own = {n: f"{n[:-1]}{count}_" for n in _OWN[head["index"]]}
            renames.update(own)
            scopes.append((indent, own))
        for old, new in renames.items():
            line = re.sub(rf"\b{old}(?![0-9A-Za-z_])", new, line)
        out.append(line)
    return out


#: a loop's header, and the names each kind of loop binds
_LOOP = re.compile(r"^\s*for (?P<index>\w+) in range\(")
_OWN = {"l_": ("l_",), "k_": ("k_", "row_")}


#: statements of the loop's body in one pass over a block, at most: a large plan's body is cut
#: into passes, its values carried from one to the next in rows of the scratch, so that the
#: compiler optimises loops of bounded size (its time grows faster than a loop's length)
PASS = 2000

#: the scratch of each type of value carried between passes (float: the block's own)
_SPILL = {"f": "S_", "i": "SI_", "b": "SL_"}
_DTYPE = {"i": "int64", "b": "bool_"}

#: a study kernel's block scratch for its designs' columns and its far samples' mask, and its
#: rows' kinds of quantity as integers
_BY_DESIGN = [
    f"    J_ = np.empty({WIDTH}, dtype=np.int64)",
    f"    M_ = np.empty({WIDTH}, dtype=np.int64)",
    "    SB_ = S_.view(np.int64)",
]

#: passes from which a kernel is split into a kernel for each (`_split`), fewer staying one
#: function: split, its compile grows about linearly, but it runs slower (a 24-point chain's
#: kernel cut into 5 functions 0.54 µs a sample, as one 0.35 µs; the 300-point chain 16 µs,
#: NumPy 7 µs; docs/design.md), so that a plan of up to about 100 points (3 passes) keeps its
#: one function
SPLIT_PASSES = 4

#: a split kernel's scratch, at most (bytes): its passes run over this many blocks of a chunk
#: at a time, each block's rows in a row of it, so that the values carried from pass to pass
#: stay in memory between the calls; a few MB, so that two threads' stay in the last-level
#: cache (the 300-point chain, a block's rows 7 MB: at 32 MB 17.2 µs a sample, at 8 MB, one
#: block a call, 15.6 µs; its dispatch, a call a pass and block, ≈ 6 % of its time)
SPLIT_SCRATCH = 8 << 20


def _split(
    head: str,
    passes: list[list[str]],
    copies: tuple[list[str], list[str]],
    last: list[str],
    hoisted: list[str],
    n_rows: int,
    spilled: dict[str, int],
    per_sample: bool,
    study: str | None,
    by_design: bool = False,
) -> list[str]:
    """The kernel of several passes as a kernel of its own for each (``pass0_`` …), compiled
    one by one, and a Python ``kernel`` (the whole kernel's arguments) that runs them one
    after another over a few blocks of the chunk at a time: each block's scratch rows are a
    row of ``S2_`` (``SI2_``, ``SL2_``: the carried integers and booleans), kept from one pass
    to the next. The first pass copies the block's inputs into its rows (``copies``: those
    copies, and the inputs' alone), each later one copies the inputs again, the same values
    (LLVM vectorises a pass's loop over the block only behind a loop that stores into the
    scratch: without it a 24-point chain's passes had 129–395 packed instructions each, with
    it 588–2,010, and ran 2× faster), the last copies its outputs out
    (and, for a kernel that keeps rows, raises the tops: ``study`` is its rows'
    kinds' line, None for a full solve's kernel; ``by_design``: a study's, each sample's
    design found in the first pass). Numba compiles each pass's loop alone
    (called from Python, no pass is inlined into another): its compile time grows with the
    plan's length, not faster. The statements are the one kernel's, to the bit."""
    found = re.search(r"def kernel\((?P<args>[^)]*)\):", head)
    assert found is not None
    args = " ".join(found["args"].split())
    sig_at = head.index("SIGNATURE = numba.void(")
    close = head.index("\n)\n", sig_at)
    scratch = "numba.float64[:, ::1], numba.int64[:, ::1], numba.bool_[:, ::1]"
    types = head[:close] + f"\n    {scratch}, numba.int64, numba.int64,\n)\n"
    decorator = head[head.index("@numba.njit(", close) :].split("\n", 1)[0]
    rows = {"f": n_rows, "i": spilled["i"], "b": spilled["b"]}
    per = max(8 * sum(rows.values()) * WIDTH, 1)
    blocks = max(1, min(64, SPLIT_SCRATCH // per))
    out = [types.rstrip("\n"), "", f"ROWS_ = {n_rows}", f"BLOCKS_ = {blocks}"]
    first, again = copies
    for k, lines in enumerate(passes):
        body = [*(first if k == 0 else again), *lines, *(last if k == len(passes) - 1 else [])]
        used = set(re.findall(r"\bK_\d+\b", "\n".join(body)))
        prologue = [h for h in hoisted if h.split(" = ")[0].strip() in used]
        if by_design and k == 0:
            prologue.append(_BY_DESIGN[0])
        if study is not None and k == len(passes) - 1:
            prologue += [_BY_DESIGN[1], study]
        views = [f"        S_ = S2_[(b0_ - lo_) // {WIDTH}]"]
        views += [f"        {_SPILL[t]} = {_SPILL[t][:-1]}2_[(b0_ - lo_) // {WIDTH}]"
                  for t in "ib" if spilled[t]]  # fmt: skip
        if study is not None and k == len(passes) - 1:
            views.append("        SB_ = S_.view(np.int64)")
        out += [
            "",
            "",
            decorator,
            f"def pass{k}_({args}, S2_, SI2_, SL2_, lo_, hi_):",
            "    nan = math.nan",
            *prologue,
            f"    for b0_ in range(lo_, hi_, {WIDTH}):",
            f"        nb_ = min({WIDTH}, hi_ - b0_)",
            *views,
            *body,
            *(["    fence()"] if k == len(passes) - 1 else []),
        ]
    call = f"({args}, S2_, SI2_, SL2_, lo_, hi_)"
    out += [
        "",
        "",
        f"def kernel({args}):",
        '    """The passes one after another, over `BLOCKS_` blocks of the chunk at a time."""',
        *([] if per_sample else _ONE_DESIGN),
        "    n_ = q.shape[1]",
        f"    S2_ = np.empty((BLOCKS_, {n_rows * WIDTH}))",
        f"    SI2_ = np.empty((BLOCKS_, {max(spilled['i'], 1) * WIDTH}), dtype=np.int64)",
        f"    SL2_ = np.empty((BLOCKS_, {max(spilled['b'], 1) * WIDTH}), dtype=np.bool_)",
        f"    for lo_ in range(0, n_, BLOCKS_ * {WIDTH}):",
        f"        hi_ = min(n_, lo_ + BLOCKS_ * {WIDTH})",
        *(f"        pass{k}_{call}" for k in range(len(passes))),
    ]
    return out


def in_passes(body: list[str], rows: int) -> tuple[list[list[str]], dict[str, int]]:
    """The loop over a block's samples of `straight_line` statements, as one pass, or cut into
    passes of at most `PASS` statements for a large plan: a name assigned in one pass and
    read in a later one is stored in a scratch row of its type (`value_types`) at the end of
    the first and read back at the start of each later one. The same values, to the bit.

    Parameters
    ----------
    body : list of str
        The loop's statements (`straight_line`).
    rows : int
        The float rows of the scratch before these (the carried floats follow them).

    Returns
    -------
    passes : list of list of str
        Each pass's loop, indented in the kernel's block loop.
    spilled : dict
        Rows added per type (``"f"``, ``"i"``, ``"b"``).
    """
    cuts = [body[k : k + PASS] for k in range(0, len(body), PASS)]
    spilled = {"f": 0, "i": 0, "b": 0}
    if len(cuts) == 1:
        loop = ["        for l_ in range(nb_):", *(f"            {line}" for line in body)]
        return [loop], spilled
    trees = [[ast.parse(line).body[0] for line in cut] for cut in cuts]
    made: dict[str, int] = {}  # each name's pass (single assignments: one)
    for k, cut in enumerate(trees):
        for st in cut:
            for target in _targets(st):
                made[target.id] = k
    types = value_types([st for cut in trees for st in cut])
    slot: dict[str, str] = {}  # a carried name's scratch element
    reads: list[list[str]] = [[] for _ in cuts]
    for k, cut in enumerate(trees):
        used = {
            n.id
            for st in cut
            for n in ast.walk(st)
            if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)
        }
        for name in sorted(used):
            if made.get(name, k) < k:
                if name not in slot:
                    kind = types[name]
                    row = spilled[kind] + (rows if kind == "f" else 0)
                    spilled[kind] += 1
                    slot[name] = f"{_SPILL[kind]}[{row * WIDTH} + l_]"
                reads[k].append(name)
    out: list[list[str]] = []
    for k, cut in enumerate(trees):
        stores = [n for n, m in made.items() if m == k and n in slot]
        own = {name: f"{name}p{k}_" for name in reads[k]}  # read back under names of its own
        for st in cut:
            for node in ast.walk(st):
                if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load):
                    node.id = own.get(node.id, node.id)
        out.append([
            "        for l_ in range(nb_):",
            *(f"            {own[name]} = {slot[name]}" for name in reads[k]),
            *(f"            {ast.unparse(st)}" for st in cut),
            *(f"            {slot[name]} = {name}" for name in stores),
        ])  # fmt: skip
    return out, spilled


def value_types(body: list[ast.stmt]) -> dict[str, str]:
    """Each assigned name's type as numba will type it: ``"f"`` (float64), ``"i"`` (int64) or
    ``"b"`` (bool), from the statements' expressions (the kernels' arithmetic: numbers,
    comparisons, ``&``/``|``/``not``, selects and ``if`` expressions, ``abs``/``max``/``min``,
    the math module's functions (``floor`` and ``ceil`` integers, ``isfinite`` … booleans),
    array reads (floats, but the integer and boolean scratch and tables); a swap of names).

    Parameters
    ----------
    body : list of ast.stmt

    Returns
    -------
    dict
    """
    env: dict[str, str] = {}

    def unify(*ts: str) -> str:
        return "f" if "f" in ts else "i" if "i" in ts else "b"

    def of(e: ast.expr) -> str:
        if isinstance(e, ast.Constant):
            v = e.value
            return "b" if isinstance(v, bool) else "i" if isinstance(v, int) else "f"
        if isinstance(e, ast.Name):
            return env.get(e.id, "i" if e.id in ("i", "l_", "b0_", "nb_", "ks", "s0") else "f")
        if isinstance(e, ast.Compare):
            return "b"
        if isinstance(e, ast.UnaryOp):
            return "b" if isinstance(e.op, ast.Not) else of(e.operand)
        if isinstance(e, ast.BinOp):
            a, b = of(e.left), of(e.right)
            if isinstance(e.op, ast.BitAnd | ast.BitOr):
                return "b" if a == b == "b" else "i"
            if isinstance(e.op, ast.Div):
                return "f"
            return unify(a, b, "i")
        if isinstance(e, ast.IfExp):
            return unify(of(e.body), of(e.orelse))
        if isinstance(e, ast.Call) and isinstance(e.func, ast.Attribute):
            if e.func.attr in ("isfinite", "isnan", "isinf"):
                return "b"
            return "i" if e.func.attr in ("floor", "ceil") else "f"  # (numba's: integers)
        if isinstance(e, ast.Call) and isinstance(e.func, ast.Name):
            if e.func.id == "_sel":
                return unify(of(e.args[1]), of(e.args[2]))
            if e.func.id in ("abs", "max", "min"):
                return unify(*(of(a) for a in e.args))
            if e.func.id == "int":
                return "i"
        if isinstance(e, ast.Subscript) and isinstance(e.value, ast.Name):
            array = e.value.id  # the kernels' arrays of integers and of booleans
            return (
                "i"
                if array in ("SI_", "J_") or array.startswith("T_")
                else ("b" if array == "SL_" else "f")
            )
        return "f"  # the math module's functions, the arctangent

    for st in body:
        if isinstance(st, ast.Assign):
            for t in _targets(st):
                env[t.id] = of(st.value)
            pairs = [
                (leaf, value)
                for group in st.targets
                if isinstance(group, ast.Tuple) and isinstance(st.value, ast.Tuple)
                for leaf, value in zip(group.elts, st.value.elts, strict=False)
            ]
            for leaf, value in pairs:  # a swap: each takes the type of the value it is given
                if isinstance(leaf, ast.Name):
                    env[leaf.id] = of(value)
    return env


#: a select as a function, not an ``if`` expression: numba gives each ``if`` expression blocks
#: of its own, and its SSA pass walks them recursively (a large model's thousands passed the
#: recursion limit, and took minutes below it); a call is one instruction there, and LLVM
#: inlines it into a select
_SELECT = """
@numba.njit(error_model="numpy", cache=True)
def _sel(c, a, b):
    return a if c else b

"""

#: a kernel for one design reads its constants once: it refuses a table of one per sample
_ONE_DESIGN = [
    "    if ks != 0:",
    '        raise ValueError("a kernel for one design, given a family")',
]


def _tables(elements: dict[str, int]) -> dict[str, list[list[int]]]:
    """Array elements of the scalar loop (``x[3, 0, i]``) → each array's rows: its indices
    before the sample's and the scratch row (``[3, 0, row]``)."""
    out: dict[str, list[list[int]]] = {}
    for text, row in elements.items():
        node = ast.parse(text, mode="eval").body
        assert isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name)
        idx = node.slice.elts if isinstance(node.slice, ast.Tuple) else [node.slice]
        lead = [ast.literal_eval(e) for e in idx[:-1]]
        out.setdefault(node.value.id, []).append([*lead, row])
    return out


def _copy(
    name: str,
    rows: list[list[int]],
    into_scratch: bool,
    by_design: bool = False,
    keep: bool = False,
) -> list[str]:
    """A loop over an array's rows, each copied between the array and its scratch row: the
    inputs chunk-relative (the constants at column ``(b0_ + l_)·ks``), the outputs into the
    whole solve's arrays from ``s0``, by streaming stores (`streaming`:
    they read no line they write); ``by_design``: the constants at the sample's design's
    column (``J_``, made for the block); ``keep``: an output row written only where
    ``keep`` has it. (The loop's own names end in ``_``: the generated loop's never do.)"""
    lead = len(rows[0]) - 1
    row = f"{name}[{', '.join(f'T_{name}[k_, {k}]' for k in range(lead))}]" if lead else name
    scratch = f"S_[T_{name}[k_, {lead}] * {WIDTH} + l_]"
    if into_scratch:  # the element read whole (a row's view made here slowed the loop 4×)
        inputs = "s0 + b0_ + l_" if name in _WRITTEN else "b0_ + l_"
        column = "J_[l_]" if by_design else "(b0_ + l_) * ks"
        sample = column if name == "K" else inputs
        copy = f"{scratch} = {row}[{sample}]"
    else:
        copy = f"stream(row_, s0 + b0_ + l_, {scratch})"
    view = [] if into_scratch else [f"            row_ = {row}"]
    loop = [*view, "            for l_ in range(nb_):", f"                {copy}"]
    if keep and not into_scratch and name in _KIND:  # a row not kept is not written
        loop = [f"            if keep[T_{name}[k_, {lead}]]:", *(f"    {line}" for line in loop)]
    return [f"        for k_ in range({len(rows)}):", *loop]


#: the precision check's kinds of quantity (`excavkin.kinematics.precision.KINDS`: length,
#: velocity, acceleration, angle, angular velocity, angular acceleration) of each written
#: array's rows, by its first index where that decides it
_KIND = {
    "x": (0,), "v": (1,), "a": (2,), "trans": (3,), "body": (3, 4, 5),
    "element": (0, 1, 2, 3, 4, 5),
}  # fmt: skip


def _kinds(writes: dict[str, list[list[int]]], n_rows: int) -> list[int]:
    """Each scratch row's kind of quantity (`_KIND`), −1 for none (an input, a constant, a
    status)."""
    out = [-1] * n_rows
    for name, rows in writes.items():
        kinds = _KIND.get(name)
        if kinds is None:
            continue
        for row in rows:
            out[row[-1]] = kinds[row[0]] if len(kinds) > 1 else kinds[0]
    return out


def _tops(status: int, near: int, n_rows: int) -> list[str]:
    """The block's far samples' (solved, no nearer a dead position than ``near_at``)
    largest magnitude of each kind of quantity, kept in ``tops`` as a float's bits without
    its sign (integers that order as the magnitudes do:
    `excavkin.kinematics.precision.largest`'s arithmetic), from the rows in the scratch. A
    solved sample's values are all finite (the finiteness check), so that each is taken
    as it is, or as 0 for a sample not far (an integer maximum, which the compiler
    vectorises)."""
    return [
        "        for l_ in range(nb_):",
        f"            ok_ = S_[{status * WIDTH} + l_] == 0.0",
        f"            far_ = ok_ & (S_[{near * WIDTH} + l_] >= near_at)",
        "            M_[l_] = 0x7FFFFFFFFFFFFFFF if far_ else 0",
        f"        for r_ in range({n_rows}):",
        "            kind_ = KIND_[r_]",
        "            if kind_ >= 0:",
        "                top_ = tops[kind_]",
        "                for l_ in range(nb_):",
        f"                    top_ = max(top_, SB_[r_ * {WIDTH} + l_] & M_[l_])",
        "                tops[kind_] = top_",
    ]


@functools.lru_cache(maxsize=16)
@one_at_a_time
def written_rows(text: str) -> tuple[dict[tuple[str, tuple[int, ...]], int], int]:
    """A kernel's rows (`vectorised` ``by_design``): each written array element's scratch
    row, by the array's name and its indices before the sample's (``("x", (3, 0))``), and
    the number of scratch rows, read from its tables.

    Parameters
    ----------
    text : str
        The kernel's source.

    Returns
    -------
    rows : dict of (str, tuple of int) to int
        (One object per source text, kept: not to be changed.)
    n_rows : int
    """
    rows: dict[tuple[str, tuple[int, ...]], int] = {}
    for line in text.splitlines():
        if line.startswith("T_") and " = np.array(" in line:
            name, _, rest = line.partition(" = np.array(")
            name = name.removeprefix("T_")
            if name in _KIND:
                for row in ast.literal_eval(rest.rpartition(", dtype")[0]):
                    rows[(name, tuple(row[:-1]))] = row[-1]
    n_rows = next(
        int(line.split("np.empty(")[1].split(")")[0]) // WIDTH
        if line.startswith("    S_")
        else int(line.removeprefix("ROWS_ = "))
        for line in text.splitlines()
        if line.startswith(("    S_ = np.empty(", "ROWS_ = "))
    )
    return rows, n_rows


def _name(node: ast.expr) -> str | None:
    return node.id if isinstance(node, ast.Name) else None


def straight_line(lines: list[str]) -> list[str]:
    """Statements rewritten so that numba sees one block of single assignments: every ``if``
    expression a call of the select ``_sel`` (both sides are evaluated: they are arithmetic,
    which cannot raise under the kernels' error model), every ``and``/``or`` a ``&``/``|``,
    and a name assigned again a new name (``st`` then ``st_2_``, ``st_3_`` …), each later
    read taking the newest.

    The same values in the same order, to the bit. But numba's SSA pass, which does the
    renaming itself, walks the blocks of every ``if`` expression recursively and scans a block
    once per use of a name assigned more than once: a large model's loop body (tens of
    thousands of statements, each step reusing its temporaries' names) passed the recursion
    limit, and took minutes below it. A name read before its first assignment (an argument,
    or a value carried from the loop's previous pass) keeps its one name throughout.

    Parameters
    ----------
    lines : list of str
        Statements, each an assignment (``=`` or an augmented one) of one target or a
        ``return``.

    Returns
    -------
    list of str
    """
    trees = [_Selects().visit(ast.parse(line).body[0]) for line in lines]
    stored: set[str] = set()
    carried: set[str] = set()
    for st in trees:  # names read before they are first assigned keep one name
        for node in ast.walk(st):
            loaded = isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)
            if loaded and node.id not in stored:  # type: ignore[attr-defined]
                carried.add(node.id)  # type: ignore[attr-defined]
        for target in _targets(st):
            stored.add(target.id)
    current: dict[str, str] = {}
    count: dict[str, int] = {}
    out = []
    for st in trees:
        for node in ast.walk(st):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load):
                node.id = current.get(node.id, node.id)
        if isinstance(st, ast.AugAssign) and isinstance(st.target, ast.Name):
            old = ast.Name(current.get(st.target.id, st.target.id), ast.Load())
            st = ast.Assign([st.target], ast.BinOp(old, st.op, st.value), lineno=0)
        for target in _targets(st):
            name = target.id
            if name not in carried:
                count[name] = count.get(name, 0) + 1
                current[name] = name if count[name] == 1 else f"{name}_{count[name]}_"
                target.id = current[name]
        out.append(ast.unparse(st))
    return out


def _inlined_straight(prelude: str) -> str:
    """The prelude's functions that numba inlines into the kernel (the arctangent), each
    body made `straight_line`: inlined as they were, their ``if`` expressions would bring
    the kernel's blocks back, once per call."""
    tree = ast.parse(prelude)
    for fn in tree.body:
        if isinstance(fn, ast.FunctionDef) and "inline=" in ast.unparse(fn.decorator_list[0]):
            doc = fn.body[:1] if isinstance(fn.body[0], ast.Expr) else []
            lines = [ast.unparse(st) for st in fn.body[len(doc) :]]
            fn.body = [*doc, *(ast.parse(line).body[0] for line in straight_line(lines))]
    return ast.unparse(tree) + "\n"


class _Selects(ast.NodeTransformer):
    """``a if c else b`` to ``_sel(c, a, b)``; ``and``/``or`` to ``&``/``|``."""

    def visit_IfExp(self, node: ast.IfExp) -> ast.AST:
        self.generic_visit(node)
        return ast.Call(ast.Name("_sel", ast.Load()), [node.test, node.body, node.orelse], [])

    def visit_BoolOp(self, node: ast.BoolOp) -> ast.AST:
        self.generic_visit(node)
        op: ast.operator = ast.BitAnd() if isinstance(node.op, ast.And) else ast.BitOr()
        out = node.values[0]
        for v in node.values[1:]:
            out = ast.BinOp(out, op, v)
        return out


def _targets(st: ast.stmt) -> list[ast.Name]:
    """The names a statement assigns (a scratch row's store assigns none)."""
    if isinstance(st, ast.Assign):
        return [t for t in st.targets if isinstance(t, ast.Name)]
    if isinstance(st, ast.AugAssign) and isinstance(st.target, ast.Name):
        return [st.target]
    return []


class _Rewriter(ast.NodeTransformer):
    """Array reads and writes to scratch rows; ``if`` blocks to selects."""

    def __init__(self, per_sample: bool) -> None:
        self.per_sample = per_sample
        self.rows: dict[str, int] = {}  # an array element's text → its row
        self.reads: dict[str, int] = {}  # copied in: source text → row
        self.writes: dict[str, int] = {}  # copied out: destination text → row
        self.hoisted: dict[str, int] = {}  # one design's constants: name → column of K
        self.defined: set[str] = {"nan", "close_tol", "singular_tol"}
        self.conditions = 0

    def row(self, node: ast.Subscript) -> str:
        text = ast.unparse(node)
        if text not in self.rows:
            self.rows[text] = len(self.rows)
        return f"S_[{self.rows[text] * WIDTH} + l_]"

    def visit_Subscript(self, node: ast.Subscript) -> ast.AST:
        array = _name(node.value)
        if array == "K" and not self.per_sample:  # one value for every sample: a scalar
            assert isinstance(node.slice, ast.Tuple)
            row = ast.literal_eval(node.slice.elts[0])
            self.hoisted[f"K_{row}"] = row
            return ast.Name(f"K_{row}", ast.Load())
        if array in _READ | _WRITTEN:
            text = ast.unparse(node)
            if array in _READ and text not in self.rows:
                self.reads[text] = len(self.rows)
            out: ast.AST = ast.parse(self.row(node), mode="eval").body
            return out
        return self.generic_visit(node)

    def visit_BoolOp(self, node: ast.BoolOp) -> ast.AST:
        # a balanced tree of & or |, not a chain: a large model's `and` of hundreds of
        # operands would nest as deep as it is long, past the recursion limit of
        # ast.unparse and of the compiler
        op: ast.operator = ast.BitAnd() if isinstance(node.op, ast.And) else ast.BitOr()
        values: list[ast.expr] = [self.visit(v) for v in node.values]
        while len(values) > 1:
            pairs = [ast.BinOp(a, op, b) for a, b in zip(values[::2], values[1::2], strict=False)]
            values = pairs + values[len(pairs) * 2 :]
        return values[0]

    def expr(self, node: ast.expr) -> str:
        return ast.unparse(self.visit(node))

    def statement(self, st: ast.stmt, cond: str | None, out: list[str]) -> None:
        if isinstance(st, ast.If):
            test = self.expr(st.test)
            self.conditions += 1
            here = f"c{self.conditions}_"
            out.append(f"{here} = {test}" if cond is None else f"{here} = {cond} & ({test})")
            for s in st.body:
                self.statement(s, here, out)
            if st.orelse:
                self.conditions += 1
                other = f"c{self.conditions}_"
                neg = f"not ({test})"
                out.append(f"{other} = {neg}" if cond is None else f"{other} = {cond} & ({neg})")
                for s in st.orelse:
                    self.statement(s, other, out)
            return
        if isinstance(st, ast.AugAssign) and cond is None:
            out.append(ast.unparse(self.visit(st)))
            return
        if isinstance(st, ast.Assign) and len(st.targets) == 1:
            target = st.targets[0]
            value = self.expr(st.value)
            if isinstance(target, ast.Name):
                name = target.id
                if cond is None or name not in self.defined:
                    out.append(f"{name} = {value}")
                else:
                    out.append(f"{name} = ({value}) if {cond} else {name}")
                self.defined.add(name)
                return
            if isinstance(target, ast.Subscript) and cond is None:
                text = ast.unparse(target)
                slot = self.row(target)
                self.writes[text] = self.rows[text]
                out.append(f"{slot} = {value}")
                return
        raise NotImplementedError(f"cannot vectorise: {ast.unparse(st)}")
