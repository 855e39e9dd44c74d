"""The device kernels of a study on an NVIDIA GPU (`excavkin.studies.device`): a sample's
precision scan, the picked samples' patch, a design's reductions and its count of poses
solved. Imported only where ``backend="cuda"`` runs (it imports numba's CUDA target; the
simulator, ``NUMBA_ENABLE_CUDASIM=1``, swaps this module's ``cuda`` for its own)."""

# mypy: ignore-errors
import math

import numpy as np
from numba import cuda

from excavkin import gpu
from excavkin.kinematics import precision
from excavkin.kinematics.kernels import Code

__all__ = ["fill", "inputs", "patch", "reduce", "scan", "solved"]

#: threads per block (`excavkin.gpu.THREADS`), the scan's shared rows
THREADS = gpu.THREADS
#: kinds of quantity (`excavkin.kinematics.precision.KINDS`)
KINDS = len(precision.KINDS)
PI = math.pi
TAU = 2.0 * math.pi
BAD_INPUT = int(Code.BAD_INPUT)
BAD_LENGTH = int(Code.BAD_LENGTH)
BAD_DESIGN = int(Code.BAD_DESIGN)


@cuda.jit
def fill(arr, value):
    i = cuda.grid(1)
    if i < arr.shape[0]:
        arr[i] = value


@cuda.jit
def inputs(by_pose, by_design, design, is_length, unbuildable, p, ins, status):
    # a thread a sample: its inputs, rates and accelerations from its pose's and its
    # design's tables, checked as excavkin.kinematics.solve.check_inputs checks them: not
    # finite, a driven length not positive (its values NaN), a design that builds no
    # mechanism (its values NaN)
    i = cuda.grid(1)
    if i >= status.shape[0]:
        return
    des = i // p
    pose = i - des * p
    n_in = design.shape[1]
    finite = True
    for k in range(3):
        for r in range(n_in):
            v = by_design[k, r, des] if design[k, r] == 1 else by_pose[k, r, pose]
            ins[k * n_in + r, i] = v
            finite = finite and math.isfinite(v)
    st = 0 if finite else BAD_INPUT
    blank = False
    if st == 0:
        for r in range(n_in):
            if is_length[r] == 1 and not ins[r, i] > 0.0:
                blank = True
        if blank:
            st = BAD_LENGTH
    if unbuildable[des] == 1:
        if st == 0:
            st = BAD_DESIGN
        blank = True
    if blank:
        for r in range(n_in):
            ins[r, i] = math.nan
    status[i] = st


@cuda.jit
def patch(arr, index, values):
    t = cuda.grid(1)
    if t < index.shape[0]:
        arr[index[t]] = values[t]


@cuda.jit
def scan(state, row_kind, status, near, near_at, block, tops, picks, count):
    # a thread a sample: its largest magnitude of each kind (far and solved), the
    # block's in shared memory, then one atomic maximum a kind; a near one picked
    i = cuda.grid(1)
    t = cuda.threadIdx.x
    top = cuda.shared.array((KINDS, THREADS), np.float64)
    for k in range(KINDS):
        top[k, t] = 0.0
    if i < status.shape[0] and status[i] == 0:
        if near[i] >= near_at:
            for r in range(state.shape[0]):
                x = abs(state[r, i])
                k = row_kind[r]
                if x > top[k, t]:
                    top[k, t] = x
        elif near[i] < near_at:
            slot = cuda.atomic.add(count, 0, 1)
            picks[slot] = i
    cuda.syncthreads()
    half = THREADS // 2
    while half > 0:
        if t < half:
            for k in range(KINDS):
                if top[k, t + half] > top[k, t]:
                    top[k, t] = top[k, t + half]
        cuda.syncthreads()
        half //= 2
    if t == 0:
        b = (cuda.blockIdx.x * THREADS) // block
        for k in range(KINDS):
            if top[k, 0] > 0.0:
                cuda.atomic.max(tops, (b, k), top[k, 0])


@cuda.jit(device=True)
def pose(row, status, at, j, target, shift, imprecise):
    # the pose's value as NumPy reduces it: minus the target, NaN where it did not solve
    x = row[at + j]
    if shift:
        x = x - target[j]
    c = status[at + j]
    return x if (c == 0 or c == imprecise) else math.nan


@cuda.jit(device=True)
def term(row, status, at, j, target, shift, how, imprecise):
    # the j-th value summed: a mean's (NaN as 0), a sum of squares', an angle's step
    if how == 10:
        a0 = pose(row, status, at, j, target, False, imprecise)
        a1 = pose(row, status, at, j + 1, target, False, imprecise)
        m = math.fmod((a1 - a0) + PI, TAU)  # NumPy's remainder: the divisor's sign
        if m != 0.0:
            if (TAU < 0.0) != (m < 0.0):
                m += TAU
        else:
            m = math.copysign(0.0, TAU)
        return m - PI
    x = pose(row, status, at, j, target, shift, imprecise)
    if how == 4:
        x = x * x
    return 0.0 if math.isnan(x) else x


@cuda.jit(device=True)
def leaf(row, status, at, target, shift, how, imprecise, start, n):
    # NumPy's sum of up to 128 values: eight running sums, then the rest one by one
    if n < 8:
        res = 0.0
        for i in range(n):
            res += term(row, status, at, start + i, target, shift, how, imprecise)
        return res
    r0 = term(row, status, at, start, target, shift, how, imprecise)
    r1 = term(row, status, at, start + 1, target, shift, how, imprecise)
    r2 = term(row, status, at, start + 2, target, shift, how, imprecise)
    r3 = term(row, status, at, start + 3, target, shift, how, imprecise)
    r4 = term(row, status, at, start + 4, target, shift, how, imprecise)
    r5 = term(row, status, at, start + 5, target, shift, how, imprecise)
    r6 = term(row, status, at, start + 6, target, shift, how, imprecise)
    r7 = term(row, status, at, start + 7, target, shift, how, imprecise)
    i = 8
    while i < n - n % 8:
        r0 += term(row, status, at, start + i, target, shift, how, imprecise)
        r1 += term(row, status, at, start + i + 1, target, shift, how, imprecise)
        r2 += term(row, status, at, start + i + 2, target, shift, how, imprecise)
        r3 += term(row, status, at, start + i + 3, target, shift, how, imprecise)
        r4 += term(row, status, at, start + i + 4, target, shift, how, imprecise)
        r5 += term(row, status, at, start + i + 5, target, shift, how, imprecise)
        r6 += term(row, status, at, start + i + 6, target, shift, how, imprecise)
        r7 += term(row, status, at, start + i + 7, target, shift, how, imprecise)
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += term(row, status, at, start + i, target, shift, how, imprecise)
        i += 1
    return res


@cuda.jit(device=True)
def pairwise(row, status, at, target, shift, how, imprecise, n):
    # NumPy's pairwise sum of n values (`excavkin.studies.reductions`'s walk, its stack
    # local to the thread)
    S = cuda.local.array(64, np.int64)
    N = cuda.local.array(64, np.int64)
    G = cuda.local.array(64, np.int64)
    L = cuda.local.array(64, np.float64)
    top = 0
    S[0] = 0
    N[0] = n
    G[0] = 0
    pending = False
    res = 0.0
    while True:
        if pending:
            if top < 0:
                return res
            if G[top] == 1:
                L[top] = res
                G[top] = 2
                half = N[top] // 2
                half -= half % 8
                top += 1
                S[top] = S[top - 1] + half
                N[top] = N[top - 1] - half
                G[top] = 0
                pending = False
            else:
                res = L[top] + res
                top -= 1
            continue
        if N[top] <= 128:
            res = leaf(row, status, at, target, shift, how, imprecise, S[top], N[top])
            top -= 1
            pending = True
        else:
            G[top] = 1
            half = N[top] // 2
            half -= half % 8
            top += 1
            S[top] = S[top - 1]
            N[top] = half
            G[top] = 0


@cuda.jit
def reduce(row, status, p, target, shift, how, imprecise, out):
    # a thread a design: its poses' values reduced as the CPU's compiled pass does
    i = cuda.grid(1)
    if i >= out.shape[0]:
        return
    at = i * p
    if how == 10:  # an angle's change: NaN unless every pose solved
        out[i] = 0.0 + pairwise(row, status, at, target, False, how, imprecise, p - 1)
        return
    if how == 8 or how == 9 or how == 5:  # first, last, change
        a = pose(row, status, at, 0, target, shift, imprecise)
        b = pose(row, status, at, p - 1, target, shift, imprecise)
        out[i] = a if how == 8 else (b if how == 9 else b - a)
        return
    count = 0
    for j in range(p):
        count += not math.isnan(pose(row, status, at, j, target, shift, imprecise))
    if count == 0:
        out[i] = math.nan
        return
    if how == 3 or how == 4:  # mean, sumsq: NaN as 0, NumPy's order
        total = 0.0 + pairwise(row, status, at, target, shift, how, imprecise, p)
        out[i] = total / count if how == 3 else total
        return
    best = math.nan
    found = -1
    low = how == 0 or how == 6
    for j in range(p):
        x = pose(row, status, at, j, target, shift, imprecise)
        if math.isnan(x):
            continue
        x = abs(x) if how == 2 else x
        if found < 0 or (x < best if low else x > best):
            best = x
            found = j
    if how == 6 or how == 7:
        edge = math.inf if how == 6 else -math.inf
        out[i] = found if best != edge else 0
    else:
        out[i] = best


@cuda.jit
def solved(status, p, imprecise, out):
    i = cuda.grid(1)
    if i < out.shape[0]:
        count = 0
        for j in range(p):
            c = status[i * p + j]
            count += c == 0 or c == imprecise
        out[i] = count
