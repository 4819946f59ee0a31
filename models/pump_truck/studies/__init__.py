"""Studies of the pump truck on Dask (``flexlib.study``): the emergency-stop envelope over start poses and
counterbalance pilot ratios (:mod:`.envelope`) and the emergency stop over manufacturing tolerances
(:mod:`.tolerances`). Each is a script (``python -m flexlib.models.pump_truck.studies.<name>``) that writes its
Parquet tables and its figure, and functions the tests call with a few variants (``docs/studies.md``)."""
