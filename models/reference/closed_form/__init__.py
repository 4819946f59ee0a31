"""Independent closed-form references of the catalogue's multibody systems (numpy/scipy only, no flexlib).

Every function states its formula, its source (textbook section or derivation) and its SI units; each one is checked
against a second, independent computation in ``tests/test_references_multibody.py`` (closed form vs. ``solve_ivp`` of
the minimal-coordinate ODE, vector loop vs. Freudenstein, virtual work vs. Newton statics, ...).

- :mod:`.pendulums`: ``pendulum_angle``, ``pendulum_period``, ``pendulum_period_small``, ``physical_pendulum_period``,
  ``double_pendulum_bodies``, ``double_pendulum_point_masses``, ``double_pendulum_rods``, ``double_pendulum_points``
- :mod:`.tops`: ``heavy_top_steady_precession``, ``heavy_top_initial_conditions``, ``symmetric_top_euler_rhs``,
  ``symmetric_top_energy``, ``euler_zxz_matrix``
- :mod:`.slider_crank`: ``slider_position``, ``slider_velocity``, ``slider_acceleration``, ``slider_dx_dtheta``,
  ``crank_torque_virtual_work``
- :mod:`.four_bar`: ``fourbar_angles``, ``fourbar_velocities``, ``coupler_point``, ``grashof``,
  ``static_fourbar_torque``, ``beam_pin_link_reactions``
"""

from .four_bar import (
    BeamReactions,
    GrashofResult,
    beam_pin_link_reactions,
    coupler_point,
    fourbar_angles,
    fourbar_velocities,
    grashof,
    static_fourbar_torque,
)
from .pendulums import (
    DoublePendulum,
    double_pendulum_bodies,
    double_pendulum_point_masses,
    double_pendulum_points,
    double_pendulum_rods,
    pendulum_angle,
    pendulum_period,
    pendulum_period_small,
    physical_pendulum_period,
)
from .slider_crank import (
    crank_torque_virtual_work,
    slider_acceleration,
    slider_dx_dtheta,
    slider_position,
    slider_velocity,
)
from .tops import (
    WORLD_Z_UP_TO_Y_UP,
    TopInitialConditions,
    euler_zxz_matrix,
    heavy_top_initial_conditions,
    heavy_top_steady_precession,
    symmetric_top_energy,
    symmetric_top_euler_rhs,
)

__all__ = [
    "WORLD_Z_UP_TO_Y_UP",
    "BeamReactions",
    "DoublePendulum",
    "GrashofResult",
    "TopInitialConditions",
    "beam_pin_link_reactions",
    "coupler_point",
    "crank_torque_virtual_work",
    "double_pendulum_bodies",
    "double_pendulum_point_masses",
    "double_pendulum_points",
    "double_pendulum_rods",
    "euler_zxz_matrix",
    "fourbar_angles",
    "fourbar_velocities",
    "grashof",
    "heavy_top_initial_conditions",
    "heavy_top_steady_precession",
    "pendulum_angle",
    "pendulum_period",
    "pendulum_period_small",
    "physical_pendulum_period",
    "slider_acceleration",
    "slider_dx_dtheta",
    "slider_position",
    "slider_velocity",
    "static_fourbar_torque",
    "symmetric_top_energy",
    "symmetric_top_euler_rhs",
]
