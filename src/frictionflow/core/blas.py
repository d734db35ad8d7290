"""Products into given room, for kernels compiled without numba's runtime (:data:`.options.NO_RUNTIME`).

``np.dot(a, x, out)`` takes numba's runtime even though it allocates
nothing; :func:`gemv` makes the very call ``a @ x`` makes (numba's own BLAS
entry point, the same arguments), so its numbers are ``@``'s bit for bit.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import make_array
from numba.np.linalg import call_xxgemv, ensure_blas


@intrinsic
def gemv(typingctx, a, x, out):
    """``out[:] = a @ x`` (``a`` a C-contiguous matrix, ``x`` and ``out`` contiguous vectors of its length and
    height, all float64 or all complex128), nothing allocated; an empty ``a`` gives zeros, as ``@`` does."""
    arrays = (a, x, out)
    if not (all(isinstance(y, types.Array) and y.layout == "C" for y in arrays)
            and (a.ndim, x.ndim, out.ndim) == (2, 1, 1)
            and a.dtype in (types.float64, types.complex128) and x.dtype == a.dtype and out.dtype == a.dtype):
        return None

    def codegen(context, builder, sig, args):
        ensure_blas()
        am, xm, om = (make_array(ty)(context, builder, v) for ty, v in zip(sig.args, args))
        shapes = cgutils.unpack_tuple(builder, am.shape)
        zero = context.get_constant(types.intp, 0)
        empty = builder.or_(builder.icmp_signed("==", shapes[0], zero), builder.icmp_signed("==", shapes[1], zero))
        with builder.if_else(empty, likely=False) as (is_empty, not_empty):
            with is_empty:
                cgutils.memset(builder, om.data, builder.mul(om.itemsize, om.nitems), 0)
            with not_empty:  # a C-ordered matrix: BLAS sees its transpose, as numba's np.dot does
                call_xxgemv(context, builder, True, sig.args[0], shapes, am.data, xm.data, om.data)
        return context.get_dummy_value()

    return types.void(a, x, out), codegen
