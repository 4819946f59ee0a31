"""The concrete-pump truck boom: design record, linkage kinematics and hand statics.

:mod:`.parameters` holds the record (``PumpTruckParameters``), :mod:`.kinematics` the planar cylinder-drive
kinematics and :mod:`.statics` the mass properties, holding torques and the cylinder sizing; :mod:`.model` the rigid
simulation model ``PumpTruck`` and :mod:`.scenarios` its scenarios, registered as ``pump-truck``
(``flexlib run pump-truck --scenario expand-fold``).
"""
