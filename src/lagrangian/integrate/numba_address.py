"""A call, from numba's compiled code, of machine code known only by its address.

SymEngine's LLVM backend (:class:`symengine.Lambdify`, ``backend="llvm"``) compiles a
system's M and f in milliseconds, where numba takes a second or more; its
``as_ctypes()`` gives the address of a function

    void call(double *out, const double *in, void *user_data)

and the ``user_data`` (the compiled code's object) to call it with.  :func:`call_address`
calls it from numba with two arrays, so that a loop compiled once on a machine
(:mod:`.numba_dop853`, ``linked_derivative``) evaluates any system's M and f without
compiling anything for that system.  The addresses are plain integers: the loop's machine
code does not depend on them, and is cached on disk like any other.  The caller keeps
the SymEngine object alive while the address is used.  Importing this module imports
numba.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def call_address(typingctx, address, user_data, out, values):
    """``address(out.data, values.data, user_data)``: out = the function at ``address`` (an
    integer) of ``values`` (1-D float64 arrays, contiguous)."""
    if not (
        isinstance(address, types.Integer)
        and isinstance(user_data, types.Integer)
        and all(
            isinstance(a, types.Array) and a.dtype == types.float64 and a.ndim == 1
            for a in (out, values)
        )
    ):
        return None

    def codegen(context, builder, signature, arguments):
        address_value, user_value, out_value, values_value = arguments
        double = ir.DoubleType().as_pointer()
        function_type = ir.FunctionType(ir.VoidType(), [double, double, cgutils.voidptr_t])
        function = builder.inttoptr(address_value, function_type.as_pointer())
        out_array = context.make_array(signature.args[2])(context, builder, out_value)
        values_array = context.make_array(signature.args[3])(context, builder, values_value)
        user = builder.inttoptr(user_value, cgutils.voidptr_t)
        builder.call(function, [out_array.data, values_array.data, user])
        return context.get_dummy_value()

    return types.void(address, user_data, out, values), codegen
