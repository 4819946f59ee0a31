"""Unit conversion constants for input and output (flexlib is SI inside).

Multiply a value given in the named unit by the constant to get SI; divide an SI
value by it to display it in that unit: ``p = 200 * units.bar``,
``q / units.L_per_min``.
"""

import math

bar = 1e5
"""1 bar in Pa."""
MPa = 1e6
"""1 MPa in Pa."""
L = 1e-3
"""1 litre in m³."""
L_per_min = 1e-3 / 60.0
"""1 L/min in m³/s."""
mm = 1e-3
"""1 mm in m."""
cm3 = 1e-6
"""1 cm³ in m³."""
deg = math.pi / 180.0
"""1 degree in rad."""
rpm = 2.0 * math.pi / 60.0
"""1 rev/min in rad/s."""
kN = 1e3
"""1 kN in N."""
g_n = 9.80665
"""Standard gravity [m/s²] (3rd CGPM, 1901; MSL ``Modelica.Constants.g_n``): the default of ``World.g``."""
