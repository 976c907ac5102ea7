"""The joint laws as numpy ufuncs (broadcasting over arrays and scalars), SI units.

Kernels import the scalar njit versions from `bbmc.laws.strength` and `bbmc.laws.stiffness`; the
ufuncs here are compiled from the very same source (see `_compile`). Arguments are positional.
"""

from bbmc.laws import mobilized as _mobilized
from bbmc.laws import stiffness as _stiffness
from bbmc.laws import strength as _strength
from bbmc.laws._compile import numpy_law

roughness_angle = numpy_law(_strength.roughness_angle)
peak_friction_angle = numpy_law(_strength.peak_friction_angle)
peak_shear_strength = numpy_law(_strength.peak_shear_strength)
exact_tangent_coefficient = numpy_law(_strength.exact_tangent_coefficient)
envelope_slope = numpy_law(_strength.envelope_slope)
equivalent_friction_angle = numpy_law(_strength.equivalent_friction_angle)
equivalent_cohesion = numpy_law(_strength.equivalent_cohesion)
scaled_jrc = numpy_law(_strength.scaled_jrc)
scaled_jcs = numpy_law(_strength.scaled_jcs)
residual_friction_angle = numpy_law(_strength.residual_friction_angle)

linear_relation = numpy_law(_stiffness.linear_relation)
initial_shear_stiffness = numpy_law(_stiffness.initial_shear_stiffness)
hyperbolic_shear_stiffness = numpy_law(_stiffness.hyperbolic_shear_stiffness)
bandis_shear_stiffness = numpy_law(_stiffness.bandis_shear_stiffness)
correction_function = numpy_law(_stiffness.correction_function)
corrected_shear_stiffness = numpy_law(_stiffness.corrected_shear_stiffness)
peak_reduction_factor = numpy_law(_stiffness.peak_reduction_factor)
simplified_shear_stiffness = numpy_law(_stiffness.simplified_shear_stiffness)
hyperbolic_shear_displacement = numpy_law(_stiffness.hyperbolic_shear_displacement)
normal_stiffness = numpy_law(_stiffness.normal_stiffness)

peak_shear_displacement = numpy_law(_mobilized.peak_shear_displacement)
mobilized_roughness_ratio = numpy_law(_mobilized.mobilized_roughness_ratio)
mobilized_friction_angle = numpy_law(_mobilized.mobilized_friction_angle)
mobilized_shear_strength = numpy_law(_mobilized.mobilized_shear_strength)
damage_coefficient = numpy_law(_mobilized.damage_coefficient)
mobilized_dilation_angle = numpy_law(_mobilized.mobilized_dilation_angle)
initial_aperture = numpy_law(_mobilized.initial_aperture)
bandis_initial_normal_stiffness = numpy_law(_mobilized.bandis_initial_normal_stiffness)
bandis_maximum_closure = numpy_law(_mobilized.bandis_maximum_closure)
bandis_closure = numpy_law(_mobilized.bandis_closure)
bandis_closure_stress = numpy_law(_mobilized.bandis_closure_stress)
bandis_normal_stiffness = numpy_law(_mobilized.bandis_normal_stiffness)

__all__ = [
    "bandis_closure",
    "bandis_closure_stress",
    "bandis_initial_normal_stiffness",
    "bandis_maximum_closure",
    "bandis_normal_stiffness",
    "bandis_shear_stiffness",
    "corrected_shear_stiffness",
    "correction_function",
    "damage_coefficient",
    "envelope_slope",
    "equivalent_cohesion",
    "equivalent_friction_angle",
    "exact_tangent_coefficient",
    "hyperbolic_shear_displacement",
    "hyperbolic_shear_stiffness",
    "initial_aperture",
    "initial_shear_stiffness",
    "linear_relation",
    "mobilized_dilation_angle",
    "mobilized_friction_angle",
    "mobilized_roughness_ratio",
    "mobilized_shear_strength",
    "normal_stiffness",
    "peak_friction_angle",
    "peak_reduction_factor",
    "peak_shear_displacement",
    "peak_shear_strength",
    "residual_friction_angle",
    "roughness_angle",
    "scaled_jcs",
    "scaled_jrc",
    "simplified_shear_stiffness",
]
