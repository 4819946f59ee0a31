"""Stage 4 — consistent initial values and event re-initialisation, split by job: the problem and its checks
(``problem``), the nonlinear solve (``newton``), re-initialisation with the states held (``reinit``), the relation
values at the start (``relations``), and the :class:`~flexlib.solve.init.initializer.Initializer` that combines them."""
