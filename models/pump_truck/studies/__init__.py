"""Studies of the pump truck on Dask (``flexlib.study``): the emergency stop over manufacturing tolerances
(:mod:`.tolerances`). Each is a script (``python -m flexlib.models.pump_truck.studies.tolerances``) that writes its
Parquet table and its figure, and a function the tests call with a few variants."""
