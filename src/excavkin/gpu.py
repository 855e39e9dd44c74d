"""The generated kernels on an NVIDIA GPU, through numba's CUDA target: one thread a sample.

Every generated source (`excavkin.kinematics.compiled`, `excavkin.kinematics.compiled_tangents`,
`excavkin.kinetostatics.compiled`) is one loop over samples whose body reads a sample's inputs
and writes its outputs, and nothing else: the samples are independent. `device_source` rewrites
such a source for the CUDA target — its loop ``for i in range(BOUND):`` becomes one thread per
sample, ``i = cuda.grid(1)`` guarded by ``if i < BOUND:``, its kernel a ``cuda.jit`` kernel and
its helper functions (the arctangent) device functions — and changes nothing else: the same
statements, in the same order, as the CPU kernel runs. `DeviceKernel` calls it with the CPU
kernel's own arguments: it copies the arrays to the device, launches a thread per sample, and
copies back the arrays the kernel writes into the caller's (views of the result, of any
layout).

``NUMBA_ENABLE_CUDASIM=1`` (set before numba is imported) runs the kernels in numba's CUDA
simulator, on the CPU, one sample at a time in Python: slow, and exact in the same way, which is
how the tests check the rewrite on a machine without a GPU.
"""

from __future__ import annotations

import ast
import math
import re
from typing import Any

import numpy as np

from excavkin.kinematics.one_at_a_time import one_at_a_time

__all__ = ["THREADS", "DeviceKernel", "device_source", "why_not"]

#: threads per block
THREADS = 128

#: ``max(a, b)`` as a device function: numba's CUDA target types the builtin ``max`` through an
#: overload of ``*args``, which its device compiler refuses ("2 argument types given, but
#: function takes 1 arguments"), though its simulator runs it. The generated sources call it
#: with two numbers (a clamp at 0); this is the builtin's rule for two: the first, unless the
#: second is greater (a NaN first stays)
_MAX2 = """

@cuda.jit(device=True, inline=True)
def _max2(a, b):
    return b if b > a else a

"""

_LOOP = re.compile(r"^(?P<indent>[ ]+)for i in range\((?P<bound>[^\n]+)\):$", re.MULTILINE)


def why_not() -> str | None:
    """Why the CUDA target cannot run here (None: it can).

    Returns
    -------
    str or None
        numba or its CUDA target cannot be imported, or no GPU (and no simulator) is usable.
    """
    try:
        from numba import cuda
    except ImportError as exc:
        return f"numba's CUDA target cannot be imported ({exc}; pip install numba-cuda)"
    try:
        usable = bool(cuda.is_available())  # type: ignore[no-untyped-call]
    except Exception as exc:  # a driver that fails to load says so its own way
        return f"the CUDA driver cannot be used ({exc})"
    if not usable:
        return (
            "no CUDA GPU is usable here (numba.cuda.is_available() is False: no NVIDIA GPU "
            "or driver; NUMBA_ENABLE_CUDASIM=1 runs numba's simulator instead)"
        )
    return None


def device_source(text: str, by_design: bool = False) -> str:
    """A generated CPU source rewritten for numba's CUDA target.

    Parameters
    ----------
    text : str
        A generated source: a ``kernel`` decorated ``@numba.njit(SIGNATURE, ...)`` whose body
        is one loop ``for i in range(BOUND):`` over samples, and helper functions decorated
        ``@numba.njit(inline="always", ...)``.
    by_design : bool
        The samples are a study's designs × poses (design-major): sample ``i`` reads the
        constants' column ``i // ks`` (``ks`` the poses per design, a column per design)
        instead of ``i * ks`` (a column per sample, or ``ks`` 0: one for all). Only for the
        kinematics' source (`excavkin.kinematics.compiled.source`), whose one column index
        is ``j = i * ks``.

    Returns
    -------
    str
        The same statements: the kernel a ``cuda.jit`` kernel, the loop one thread a sample,
        the helpers device functions, ``max(a, b)`` a device function of its own (`_MAX2`).

    Raises
    ------
    ValueError
        The text is not such a source.
    """
    if by_design:
        text, columns = re.subn(r"^(\s+)j = i \* ks$", r"\1j = i // ks", text, flags=re.M)
        if columns != 1:
            raise ValueError("not a kinematics source: one column index j = i * ks")
    out = text.replace("import numba\n", "import numba\nfrom numba import cuda\n" + _MAX2, 1)
    out = re.sub(r"\bmax\(", "_max2(", out)
    out, helpers = re.subn(
        r'@numba\.njit\(inline="always"[^)]*\)', "@cuda.jit(device=True, inline=True)", out
    )
    out, kernels = re.subn(r"@numba\.njit\(SIGNATURE[^)]*\)", "@cuda.jit", out)
    loop = _LOOP.search(out, out.index("def kernel(") if "def kernel(" in out else 0)
    if kernels != 1 or loop is None:
        raise ValueError("not a generated source: one kernel with a loop over samples")
    indent, bound = loop["indent"], loop["bound"]
    guard = f"{indent}i = cuda.grid(1)\n{indent}if i < {bound}:"
    return out[: loop.start()] + guard + out[loop.end() :]


@one_at_a_time
def _kernel_of(text: str) -> ast.FunctionDef:
    """The ``kernel`` function of a generated source, parsed."""
    tree = ast.parse(text)
    return next(f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "kernel")


class DeviceKernel:
    """A device kernel called as its CPU kernel is: with host arrays.

    Parameters
    ----------
    kernel : numba CUDA kernel
        The ``kernel`` of a `device_source`.
    text : str
        That source: the kernel's parameters, which of them it writes, and the loop's bound
        are read from it.
    """

    def __init__(self, kernel: Any, text: str) -> None:
        fn = _kernel_of(text)
        self.kernel = kernel
        self.params = [a.arg for a in fn.args.args]
        written: set[str] = set()
        for node in ast.walk(fn):
            targets = node.targets if isinstance(node, ast.Assign) else []
            for t in targets:
                for leaf in ast.walk(t):
                    if isinstance(leaf, ast.Subscript) and isinstance(leaf.value, ast.Name):
                        written.add(leaf.value.id)
        self.written = written & set(self.params)
        guard = next(n for n in ast.walk(fn) if isinstance(n, ast.If))
        bound = ast.unparse(guard.test.comparators[0])  # type: ignore[attr-defined]
        found = re.fullmatch(r"(\w+)\.shape\[(\d+)\]", bound)
        if found is None or found[1] not in self.params:
            raise ValueError(f"the loop's bound {bound!r} is not an argument's length")
        #: the samples: the length of this argument's axis
        self.bound = (self.params.index(found[1]), int(found[2]))

    def __call__(self, *args: Any) -> None:
        """Run over every sample: the arrays copied in, the written ones copied back.

        Parameters
        ----------
        *args
            The CPU kernel's arguments, in its order.
        """
        from numba import cuda

        if len(args) != len(self.params):
            raise TypeError(f"the kernel takes {len(self.params)} arguments, got {len(args)}")
        n = int(args[self.bound[0]].shape[self.bound[1]])
        if n == 0:
            return
        device = [
            cuda.to_device(np.ascontiguousarray(a)) if isinstance(a, np.ndarray) else a
            for a in args
        ]
        blocks = math.ceil(n / THREADS)
        self.kernel[blocks, THREADS](*device)
        for name, host, dev in zip(self.params, args, device, strict=True):
            if name in self.written:
                host[...] = dev.copy_to_host()
