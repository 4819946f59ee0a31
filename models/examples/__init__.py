"""Example models with a default experiment, one subpackage per domain (MSL ``Examples``)."""
