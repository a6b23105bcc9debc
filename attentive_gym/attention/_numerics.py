"""Compiled building blocks that repeat numpy's arithmetic exactly (internal).

The model's compiled kernels must give the same floats as the numpy expressions they
replace, so every reduction here follows the order of the routine numpy uses:

- ``pairwise_sum``: ``np.add.reduce`` of a contiguous float64 array (numpy's pairwise
  summation with 8 accumulators over blocks of 128).
- ``vecmat``: ``w @ A`` / ``np.dot(w, A)`` for a vector ``w`` and a C-contiguous matrix,
  which numpy hands to BLAS ``dgemv``; the order is that of OpenBLAS's x86-64 ``dgemv_n``
  kernels (columns in blocks of 4, then 2, then 1, fused multiply-adds inside a block).
- ``interp``, ``interp_sorted``: ``np.interp`` (numpy's ``arr_interp``) at one point, or
  at increasing points.
- ``fma``: a fused multiply-add (one rounding), as the BLAS kernels use.
- ``shaped``: ``flat.reshape(shape)`` of a contiguous vector, without numba's general
  reshape (not a reduction: it only builds a view, far cheaper).

Everything is non-recursive: numba's on-disk cache does not reload recursive functions
reliably. The cache (``cache=True``, in ``__pycache__``) keys a compiled function on its own
source file only, so a kernel elsewhere that calls a function of this module would keep its
cached copy after this file changes; ``attentive_gym._kernel_cache`` discards the package's
cached kernels at import whenever the source they depend on changed.

Small kernels that the model's step calls in its loops are compiled ``inline="always"``:
inlined into their caller, the views of per-track rows (or the arrays) they take need no
reference counting, two atomic operations per array and call otherwise.
"""

from __future__ import annotations

import math

from llvmlite import ir
from numba import njit
from numba.core import cgutils, types
from numba.core.imputils import impl_ret_borrowed
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array

__all__ = ["fma", "shaped", "pairwise_sum", "vecmat", "interp", "interp_sorted"]


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` with a single rounding (LLVM's ``llvm.fma.f64``); float64 only."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [double], ir.FunctionType(double, [double] * 3))
        return builder.call(fn, args)

    return sig, codegen


@intrinsic
def shaped(typingctx, flat, shape):
    """``flat.reshape(shape)`` for a 1-D C-contiguous ``flat`` whose size is the product of
    ``shape`` (a tuple of ints; the caller guarantees it, nothing checks): a C-contiguous
    view of the same data and owner.

    numba's ``reshape`` checks the size and calls a C helper for the strides, about 70 ns
    a call; this builds the view's shape and strides inline (a few ns), which matters to a
    step that lays out some twenty fields of its state buffers this way.
    """
    if not (
        isinstance(flat, types.Array)
        and flat.ndim == 1
        and flat.layout == "C"
        and isinstance(shape, types.UniTuple)
        and isinstance(shape.dtype, types.Integer)
    ):
        return None
    ndim = shape.count
    view_type = flat.copy(ndim=ndim, layout="C")

    def codegen(context, builder, signature, args):
        source = make_array(flat)(context, builder, args[0])
        dims = [context.cast(builder, d, shape.dtype, types.intp) for d in cgutils.unpack_tuple(builder, args[1])]
        strides = [source.itemsize]
        for d in reversed(dims[1:]):  # C order: each stride the next one times that dimension
            strides.insert(0, builder.mul(strides[0], d))
        view = make_array(view_type)(context, builder)
        populate_array(
            view,
            data=source.data,
            shape=dims,
            strides=strides,
            itemsize=source.itemsize,
            meminfo=source.meminfo,
            parent=source.parent,
        )
        return impl_ret_borrowed(context, builder, view_type, view._getvalue())

    return view_type(flat, shape), codegen


@njit(cache=True)
def _pairwise_block(a, lo, n):
    """numpy's pairwise summation of ``a[lo:lo + n]`` for ``n <= 128`` (one block)."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[lo + i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    m = n - n % 8
    while i < m:
        r0 += a[lo + i]
        r1 += a[lo + i + 1]
        r2 += a[lo + i + 2]
        r3 += a[lo + i + 3]
        r4 += a[lo + i + 4]
        r5 += a[lo + i + 5]
        r6 += a[lo + i + 6]
        r7 += a[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@njit(cache=True)
def _pairwise_halves(a, lo, n):
    """numpy's pairwise summation for ``n <= 256``: blocks, or two halves of blocks."""
    if n <= 128:
        return _pairwise_block(a, lo, n)
    n2 = n // 2
    n2 -= n2 % 8
    return _pairwise_block(a, lo, n2) + _pairwise_block(a, lo + n2, n - n2)


@njit(cache=True)
def pairwise_sum(a, lo, n):
    """``sum(a[lo:lo + n])`` in the order of numpy's pairwise summation (``np.add.reduce``
    of a contiguous array), for ``n <= 496`` (two levels of halves)."""
    if n <= 128:
        return _pairwise_block(a, lo, n)
    n2 = n // 2
    n2 -= n2 % 8
    return _pairwise_halves(a, lo, n2) + _pairwise_halves(a, lo + n2, n - n2)


@njit(cache=True)
def vecmat(w, A, out):
    """``out[:] = w @ A`` for ``w`` ``(K,)`` and ``A`` ``(K, N)``, summed like OpenBLAS's dgemv.

    For each column n, the rows of ``A`` go in blocks of 4 (``t = w1·a1``, then fused
    ``w0·a0``, ``w2·a2``, ``w3·a3`` into t), a block of 2 (``t = w1·a1``, fused ``w0·a0``)
    and a last single row (``w·a``, rounded), each block's t added to the running sum.
    This equals ``np.dot(w, A)`` bit for bit where numpy uses OpenBLAS's x86-64 dgemv_n
    kernel and N is a multiple of 4 (checked on AVX-512 for the model's shapes); with
    another BLAS it may differ in the last bit, as np.dot itself does between machines.
    """
    K, N = A.shape
    out[:] = 0.0
    k = 0
    while k + 4 <= K:
        w0, w1, w2, w3 = w[k], w[k + 1], w[k + 2], w[k + 3]
        for n in range(N):  # contiguous in n: vectorised, each out[n] summed as above
            t = w1 * A[k + 1, n]
            t = fma(w0, A[k, n], t)
            t = fma(w2, A[k + 2, n], t)
            t = fma(w3, A[k + 3, n], t)
            out[n] = out[n] + t
        k += 4
    if K - k >= 2:
        w0, w1 = w[k], w[k + 1]
        for n in range(N):
            out[n] = out[n] + fma(w0, A[k, n], w1 * A[k + 1, n])
        k += 2
    if K - k == 1:
        w0 = w[k]
        for n in range(N):
            out[n] = out[n] + w0 * A[k, n]


@njit(cache=True, inline="always")
def interp(x, xp, fp):
    """``np.interp(x, xp, fp)`` for a scalar x and non-decreasing ``xp`` (len >= 2); the
    arithmetic of ``interp_sorted``, the interval found by bisection."""
    n = xp.shape[0]
    if math.isnan(x):
        return x
    if x > xp[n - 1]:
        return fp[n - 1]
    if x < xp[0]:
        return fp[0]
    lo, hi = 0, n
    while lo < hi:  # the last j with xp[j] <= x
        mid = lo + ((hi - lo) >> 1)
        if x >= xp[mid]:
            lo = mid + 1
        else:
            hi = mid
    j = lo - 1
    if j == n - 1 or xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    value = slope * (x - xp[j]) + fp[j]
    if math.isnan(value):
        value = slope * (x - xp[j + 1]) + fp[j + 1]
        if math.isnan(value) and fp[j] == fp[j + 1]:
            value = fp[j]
    return value


@njit(cache=True)
def interp_sorted(x, xp, fp, out):
    """``out[:] = np.interp(x, xp, fp)`` for non-decreasing ``x`` and ``xp`` (len >= 2),
    with numpy's arithmetic (``arr_interp``): ``fp[0]`` left of ``xp``, ``fp[-1]`` right of
    it, ``fp[j]`` at a knot, else ``slope·(x − xp[j]) + fp[j]`` on the last knot interval
    holding x (found by one sweep over the knots, numpy's search gives the same j)."""
    n = xp.shape[0]
    j = 0
    for i in range(x.shape[0]):
        xi = x[i]
        if math.isnan(xi):
            out[i] = xi
            continue
        if xi > xp[n - 1]:
            out[i] = fp[n - 1]
            continue
        if xi < xp[0]:
            out[i] = fp[0]
            continue
        while j + 1 < n and xp[j + 1] <= xi:  # the last j with xp[j] <= xi
            j += 1
        if j == n - 1 or xp[j] == xi:
            out[i] = fp[j]
            continue
        slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
        value = slope * (xi - xp[j]) + fp[j]
        if math.isnan(value):  # numpy's fallback: the other end, then a flat interval
            value = slope * (xi - xp[j + 1]) + fp[j + 1]
            if math.isnan(value) and fp[j] == fp[j + 1]:
                value = fp[j]
        out[i] = value
