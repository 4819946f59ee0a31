"""Registration of the boom proxy (``models/boom_proxy.py``) for ``flexlib list`` / ``flexlib run``.

Kept beside the model in its own module because ``boom_proxy.py`` itself is a fixed benchmark model. Model option
``linkages`` (bool): joints 2–5 through four-bar linkages (default) or driven directly.
"""

from __future__ import annotations

from flexlib.models.boom_proxy import T_RAMP, BoomProxy
from flexlib.registry import ModelOption, Scenario, register_model

__all__ = ["OPTIONS"]

#: The model options of ``boom-proxy`` (checked by the registry before :class:`BoomProxy`, which reads them
#: with ``bool()``, is built).
OPTIONS = (ModelOption("linkages", bool, True, "joints 2-5 through four-bar linkages (false: driven directly by "
                       "their cylinders)"),)


def _factory(scenario: Scenario) -> BoomProxy:
    return BoomProxy(**scenario.options)


register_model(
    "boom-proxy", _factory,
    doc="five-section rigid hydraulic boom, four-bar linkages, PI joint control (issue 9 proxy)",
    scenarios=[
        Scenario("ramp", f"all five joint set-points ramp by ±10° over {T_RAMP:g} s", t_end=T_RAMP,
                 options={"linkages": True}, run={"dt_out": 0.01}),
        Scenario("ramp-direct", "the same with joints 2–5 driven directly by their cylinders", t_end=T_RAMP,
                 options={"linkages": False}, run={"dt_out": 0.01}),
        Scenario("start", "the first 2 s of the ramp", t_end=2.0, options={"linkages": True},
                 run={"dt_out": 0.01}),
    ],
    summary_signals=[f"cylinder{n}.cylinder.{v}" for n in range(1, 6) for v in ("p_A", "p_B", "q_A")]
    + [f"joint{n}.phi" for n in range(1, 6)],
    options=OPTIONS, data=(),
)
