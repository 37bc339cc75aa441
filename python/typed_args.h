// SPDX-License-Identifier: MIT
// Typed stand-ins for `py::handle` parameters: help(), __doc__ and the .pyi stub show what is expected.
#pragma once

#include <pybind11/pybind11.h>

namespace dualgraph::python {

/// A parameter taken as any Python object, checked and converted by arrays.h (so its errors name the argument
/// and the offending entry, as before); only its name in signatures differs from `py::handle`.
template <int Kind>
struct TypedObject {
  pybind11::object object;
  operator pybind11::handle() const { return object; }  // NOLINT: passes straight to the arrays.h checks
  bool is_none() const { return object.is_none(); }
};

using ArrayLike = TypedObject<0>;          ///< numpy.typing.ArrayLike
using OptionalArrayLike = TypedObject<1>;  ///< typing.Optional[numpy.typing.ArrayLike]
using IdsLike = TypedObject<2>;            ///< an id or an array-like of ids
using OptionalIdsLike = TypedObject<3>;    ///< the same or None (all)
using GateMapLike = TypedObject<4>;        ///< {gate_id: pose}
using TrajectoryLike = TypedObject<5>;     ///< a file path, an (n, 8) array or (times, poses)
using ResidualCallback = TypedObject<6>;   ///< estimates -> (d,)
using JacobianCallback = TypedObject<7>;   ///< estimates -> [(d, dof_i)], or None
using PathLike = TypedObject<8>;           ///< str or os.PathLike

}  // namespace dualgraph::python

namespace pybind11::detail {

#define DUALGRAPH_TYPED_OBJECT(KIND, NAME)                                                       \
  template <>                                                                                    \
  struct type_caster<dualgraph::python::TypedObject<KIND>> {                                     \
    PYBIND11_TYPE_CASTER(dualgraph::python::TypedObject<KIND>, const_name(NAME));                \
    bool load(handle source, bool) {                                                             \
      value.object = reinterpret_borrow<object>(source);                                         \
      return true;                                                                               \
    }                                                                                            \
    static handle cast(const dualgraph::python::TypedObject<KIND>& v, return_value_policy, handle) { \
      return v.object.inc_ref();                                                                 \
    }                                                                                            \
  };

DUALGRAPH_TYPED_OBJECT(0, "numpy.typing.ArrayLike")
DUALGRAPH_TYPED_OBJECT(1, "typing.Optional[numpy.typing.ArrayLike]")
DUALGRAPH_TYPED_OBJECT(2, "typing.Union[int, numpy.typing.ArrayLike]")
DUALGRAPH_TYPED_OBJECT(3, "typing.Union[int, numpy.typing.ArrayLike, None]")
DUALGRAPH_TYPED_OBJECT(4, "typing.Mapping[int, numpy.typing.ArrayLike]")
DUALGRAPH_TYPED_OBJECT(5, "typing.Union[str, os.PathLike, numpy.typing.ArrayLike, typing.Tuple[numpy.typing.ArrayLike, numpy.typing.ArrayLike]]")
DUALGRAPH_TYPED_OBJECT(6, "typing.Callable[[typing.List[numpy.ndarray]], numpy.typing.ArrayLike]")
DUALGRAPH_TYPED_OBJECT(7, "typing.Optional[typing.Callable[[typing.List[numpy.ndarray]], typing.Sequence[numpy.typing.ArrayLike]]]")
DUALGRAPH_TYPED_OBJECT(8, "typing.Union[str, os.PathLike]")

#undef DUALGRAPH_TYPED_OBJECT

}  // namespace pybind11::detail
