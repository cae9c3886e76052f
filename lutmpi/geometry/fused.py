"""A wheelset-frame point in the track frame, ``G + R c``, in compiled code with the same bits on
every CPU.

numba's ``np.dot`` hands even a 3-vector to OpenBLAS, whose kernel (and so the last bit of the
product) depends on the CPU OpenBLAS detects: with ``OPENBLAS_CORETYPE=Prescott`` the rigid
contact points of the reference tables moved in their last bit and, through the mesh methods'
rigid start, those methods' roll, ``x_g`` and forces (2026-11-28, the paper and Manchester
checksums). :func:`body_to_track` computes the product with explicit fused multiply-adds in
the order of OpenBLAS's Haswell ``dgemv`` kernel -- what x86-64 machines with AVX2 and FMA ran
(AMD EPYC, Intel Xeon with AVX-512: the stored checksums agreed there) -- so the tables keep
those bits and no longer depend on the kernel. ``llvm.fma`` rounds once, whatever the machine:
an FMA instruction where there is one, the C library's ``fma`` where there is none.
"""

from __future__ import annotations

from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (IEEE 754 fusedMultiplyAdd), float64; compiled code only."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
        return builder.call(fn, args)

    return sig, codegen


@njit(cache=True)
def fma_py(a, b, c):
    """:func:`fma` callable from Python (tests)."""
    return fma(a, b, c)


@njit(cache=True)
def body_to_track(R, c0, c1, c2, g0, g1, g2):
    """The track-frame point ``G + R c`` of the wheelset-frame point ``c = (c0, c1, c2)`` (m),
    ``R`` the wheelset's rotation (3, 3), ``G = (g0, g1, g2)`` its centre (m). Each row is
    ``g_i + fma(R_i2, c2, fma(R_i0, c0, R_i1 c1))``: the bits of ``G + np.dot(c, R.T)`` on
    OpenBLAS's Haswell kernel, signed zeros included (tested against exact arithmetic)."""
    x = g0 + fma(R[0, 2], c2, fma(R[0, 0], c0, R[0, 1] * c1))
    y = g1 + fma(R[1, 2], c2, fma(R[1, 0], c0, R[1, 1] * c1))
    z = g2 + fma(R[2, 2], c2, fma(R[2, 0], c0, R[2, 1] * c1))
    return x, y, z
