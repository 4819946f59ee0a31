"""The 32 m four-section Z-fold concrete-pump boom, composed from the boom parts (:mod:`flexlib.models.boom`) on
its design record :data:`~models.pump_truck.record32.BOOM32`: :class:`Boom32`, registered with its scenarios as
``boom-32`` (:mod:`.scenarios`; ``flexlib run boom-32 --scenario expand-fold``). See ``docs/boom32.md``."""

from .model import EXTENDED_POSE_DEG, JOINTS, TRANSPORT_POSE_DEG, WORKING_POSE_DEG, Boom32

__all__ = ["EXTENDED_POSE_DEG", "JOINTS", "TRANSPORT_POSE_DEG", "WORKING_POSE_DEG", "Boom32"]
