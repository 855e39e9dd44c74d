"""A generated scalar loop over samples cut into kernels of bounded length.

numba's compile of one function (its own passes and LLVM's) grows faster than its length: the
forces kernel of a chain of 300 points, one loop of some 22,000 statements, took eleven
minutes. Here such a source (a ``kernel`` whose body is one loop ``for i in range(BOUND):``
over samples, as `excavkin.kinetostatics.compiled` writes it) is rewritten as several
kernels, ``pass0_``, ``pass1_`` …, each the loop over the same samples with `PASS` of its
statements, compiled one by one, and a Python ``kernel`` of the same arguments that runs them
one after another over `SCRATCH` bytes' worth of samples at a time. The statements are first
reordered (`sunk`) so that few values cross from one pass to another. A value made in one
pass and used in a later one is stored, at the end of its pass, in a scratch array of its
type (float, integer, boolean: `excavkin.kinematics.vectorise.value_types`), a row a sample,
and read back at the start of each pass that uses it. Each pass is a kernel called from
Python, not from another kernel: no pass is inlined into another, so that the compile time
grows with the length, not faster. The arithmetic is the one loop's, on the same values: the
same numbers, to the bit (tested).
"""

from __future__ import annotations

import ast
import functools
import re

from excavkin.kinematics.one_at_a_time import one_at_a_time
from excavkin.kinematics.vectorise import value_types

__all__ = ["PASS", "SCRATCH", "split", "sunk"]

#: top-level statements of the loop in one pass, at most
PASS = 2000

#: a split kernel's carried values, at most (bytes): it runs its passes over this many bytes'
#: worth of samples at a time
SCRATCH = 16 << 20

#: each type's scratch: its name in a pass, and its NumPy type
_SCRATCH = {"f": ("SF_", "np.float64"), "i": ("SI_", "np.int64"), "b": ("SB_", "np.bool_")}
_NUMBA = "numba.float64[:, ::1], numba.int64[:, ::1], numba.boolean[:, ::1]"


@functools.lru_cache(maxsize=16)
@one_at_a_time
def split(text: str) -> str:
    """The generated source ``text`` as kernels of at most `PASS` statements each, run one
    after another by a Python ``kernel`` of the same arguments; ``text`` itself where its loop
    is no longer than that.

    Parameters
    ----------
    text : str
        A generated source: a ``kernel`` decorated ``@numba.njit(SIGNATURE, ...)`` whose
        body is one loop ``for i in range(BOUND):`` over samples, whose statements read and
        write the sample ``i`` of its arrays only.

    Returns
    -------
    str
    """
    tree = ast.parse(text)
    fn = next(f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "kernel")
    loop = fn.body[-1]
    if not (isinstance(loop, ast.For) and len(fn.body) == 1) or len(loop.body) <= PASS:
        return text
    assert isinstance(loop.target, ast.Name) and loop.target.id == "i"
    body = sunk([_flag(st) for st in loop.body])
    cuts = [body[k : k + PASS] for k in range(0, len(body), PASS)]
    args = [a.arg for a in fn.args.args]
    assigned = [_assigned(cut) for cut in cuts]
    used = [_names(cut) for cut in cuts]
    types = value_types([n for cut in cuts for st in cut for n in ast.walk(st)
                         if isinstance(n, ast.stmt)])  # fmt: skip
    slot: dict[str, tuple[str, int]] = {}  # a carried name's scratch and column
    counts = {"f": 0, "i": 0, "b": 0}
    loads: list[list[str]] = []
    stores: list[list[str]] = []
    for k in range(len(cuts)):
        before = set().union(*assigned[:k]) if k else set()
        later = set().union(*used[k + 1 :]) if k + 1 < len(cuts) else set()
        loads.append(sorted(used[k] & before))
        stores.append(sorted(assigned[k] & later))
        for name in stores[-1]:
            if name not in slot:
                kind = types.get(name, "f")
                slot[name] = (kind, counts[kind])
                counts[kind] += 1
    head = text[: text.index("@numba.njit(SIGNATURE")]
    decorator = text[text.index("@numba.njit(SIGNATURE") :].split("\n", 1)[0]
    close = _closing(head, head.index("SIGNATURE = numba.void(") + len("SIGNATURE = numba.void"))
    bound = ast.unparse(loop.iter)
    params = ", ".join([*args, "SF_", "SI_", "SB_", "lo_", "hi_"])
    width = 8 * max(sum(counts.values()), 1)
    samples = max(64, min(4096, SCRATCH // width))
    out = [
        head[:close].rstrip().rstrip(",") + f",\n    {_NUMBA}, numba.int64, numba.int64,\n)\n",
        f"SAMPLES_ = {samples}",
    ]
    for k, cut in enumerate(cuts):
        out += [
            "",
            "",
            decorator,
            f"def pass{k}_({params}):",
            "    for i in range(lo_, hi_):",
            "        r_ = i - lo_",
            *(f"        {name} = {_at(slot[name])}" for name in loads[k]),
            *(_indent(ast.unparse(st), "        ") for st in cut),
            *(f"        {_at(slot[name])} = {name}" for name in stores[k]),
        ]
    call = f"pass{{}}_({params})"
    out += [
        "",
        "",
        f"def kernel({', '.join(args)}):",
        '    """The passes one after another, over `SAMPLES_` samples at a time."""',
        f"    n_ = {bound.removeprefix('range(').removesuffix(')')}",
        *(
            f"    {_SCRATCH[t][0]} = np.empty((SAMPLES_, {max(counts[t], 1)}), "
            f"dtype={_SCRATCH[t][1]})"
            for t in "fib"
        ),
        "    for lo_ in range(0, n_, SAMPLES_):",
        "        hi_ = min(n_, lo_ + SAMPLES_)",
        *(f"        {call.format(k)}" for k in range(len(cuts))),
    ]
    text = "\n".join(out) + "\n"
    if not re.search(r"^import numpy as np$", text, re.MULTILINE):
        text = text.replace("import numba\n", "import numba\nimport numpy as np\n", 1)
    return text


def sunk(body: list[ast.stmt]) -> list[ast.stmt]:
    """The statements reordered so that few values are live at any point (the values a pass
    hands to the next): a value is made just before the first statement that reads it (the
    forces' loads of every body, made first, are read one step after another down the
    plan), and a value that only outputs read is made, and stored, as soon as what it reads
    is. Moved: an assignment of one name assigned nowhere else, of an expression that reads
    only such names, the loop's other names and arrays the loop does not write, so that it
    computes the same value wherever it stands; and a store of such a value into an output
    (an array the loop never reads, each element stored once). The others keep their order.
    The same arithmetic on the same values: the same numbers, to the bit.

    Parameters
    ----------
    body : list of ast.stmt
        The loop's statements.

    Returns
    -------
    list of ast.stmt
    """
    stores, made, written, loaded, elements = _assignments(body)
    reads = [
        {n.id for n in ast.walk(st) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
        for st in body
    ]
    free: set[int] = set()  # statements that may move
    outputs: set[int] = set()
    for k, st in enumerate(body):
        if not isinstance(st, ast.Assign) or len(st.targets) != 1:
            continue
        if any(stores.get(r, 1) != 1 for r in reads[k]):
            continue
        target = st.targets[0]
        if isinstance(target, ast.Name) and stores[target.id] == 1:
            arrays = {
                ast.unparse(n.value) for n in ast.walk(st.value) if isinstance(n, ast.Subscript)
            }
            if not arrays & written:
                free.add(k)
        elif isinstance(target, ast.Subscript):
            array = ast.unparse(target.value)
            if array not in loaded and elements[ast.unparse(target)] == 1:
                free.add(k)
                outputs.add(k)
    deps = [  # the statements of the values it reads, assigned once (always before it)
        sorted({made[r] for r in reads[k] if r in made and stores[r] == 1 and made[r] < k})
        for k in range(len(body))
    ]
    readers: list[list[int]] = [[] for _ in body]
    for k, ds in enumerate(deps):
        for d in ds:
            readers[d].append(k)
    eager = set(outputs)  # outputs, and values only outputs read: made as soon as they can
    for k in range(len(body) - 1, -1, -1):
        if k in free and readers[k] and all(r in eager for r in readers[k]):
            eager.add(k)
    waiting = {k: len(deps[k]) for k in eager}
    placed: set[int] = set()
    out: list[ast.stmt] = []

    def emit(k: int) -> None:  # k, then each eager statement it makes ready
        ready = [k]
        while ready:
            top = ready.pop()
            placed.add(top)
            out.append(body[top])
            for r in readers[top]:
                if r in eager and r not in placed:
                    waiting[r] -= 1
                    if waiting[r] == 0:
                        ready.append(r)

    def place(k: int) -> None:  # k after the statements it reads (the lazy ones just before)
        stack = [(k, [d for d in reversed(deps[k]) if d not in placed])]
        while stack:
            top, todo = stack[-1]
            while todo and todo[-1] in placed:
                todo.pop()
            if todo:
                d = todo.pop()
                stack.append((d, [e for e in reversed(deps[d]) if e not in placed]))
                continue
            stack.pop()
            if top not in placed:
                emit(top)

    for k in range(len(body)):
        if k in placed:
            continue
        if k not in free:
            place(k)
        elif k in eager and waiting[k] == 0:
            emit(k)  # (an output of nothing the loop makes)
    for k in range(len(body)):  # read by no statement that stays: in their order
        if k not in placed:
            place(k)
    return out


def _assignments(
    body: list[ast.stmt],
) -> tuple[dict[str, int], dict[str, int], set[str], set[str], dict[str, int]]:
    """`sunk`'s survey of the statements: each name's number of assignments and its (last)
    assigning statement, the arrays written and read, and each array element's number of
    stores."""
    stores: dict[str, int] = {}
    made: dict[str, int] = {}
    written: set[str] = set()
    loaded: set[str] = set()
    elements: dict[str, int] = {}
    for k, st in enumerate(body):
        for n in ast.walk(st):
            if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store):
                stores[n.id] = stores.get(n.id, 0) + 1
                made[n.id] = k
            if isinstance(n, ast.Subscript):
                array = ast.unparse(n.value)
                if isinstance(n.ctx, ast.Store):
                    written.add(array)
                    elements[ast.unparse(n)] = elements.get(ast.unparse(n), 0) + 1
                else:
                    loaded.add(array)
    return stores, made, written, loaded, elements


def _flag(st: ast.stmt) -> ast.stmt:
    """A flag raised in a branch (``if c: sg = True``) as one assignment (``sg = sg | (c)``):
    the same value, and no block of its own (numba's SSA pass goes over a name's blocks once
    for each of its assignments: a large model's forces raise hundreds of flags)."""
    if not isinstance(st, ast.If) or st.orelse or len(st.body) != 1:
        return st
    (inner,) = st.body
    if (
        isinstance(inner, ast.Assign)
        and len(inner.targets) == 1
        and isinstance(inner.targets[0], ast.Name)
        and isinstance(inner.value, ast.Constant)
        and inner.value.value is True
    ):
        name = inner.targets[0].id
        flag = ast.BinOp(ast.Name(name, ast.Load()), ast.BitOr(), st.test)
        return ast.Assign([ast.Name(name, ast.Store())], flag, lineno=0)
    return st


def _closing(text: str, at: int) -> int:
    """The index of the parenthesis closing the one at ``at``."""
    depth = 0
    for k in range(at, len(text)):
        depth += {"(": 1, ")": -1}.get(text[k], 0)
        if depth == 0:
            return k
    raise ValueError("an unclosed parenthesis")


def _at(where: tuple[str, int]) -> str:
    return f"{_SCRATCH[where[0]][0]}[r_, {where[1]}]"


def _indent(text: str, indent: str) -> str:
    return "\n".join(indent + line for line in text.splitlines())


def _assigned(cut: list[ast.stmt]) -> set[str]:
    """The names the statements assign (in any branch)."""
    return {
        n.id
        for st in cut
        for n in ast.walk(st)
        if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)
    }


def _names(cut: list[ast.stmt]) -> set[str]:
    """Every name the statements read or assign: a name assigned in a branch keeps its value
    where the branch is not taken, so that its value before is needed too."""
    return {n.id for st in cut for n in ast.walk(st) if isinstance(n, ast.Name)}
