"""Results: access by name, plots, HDF5 files."""
