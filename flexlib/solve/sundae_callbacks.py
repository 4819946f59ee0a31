"""scikit-sundae's IDA callbacks on CasADi FunctionBuffers (residual, iteration matrix, event indicators) for the
adapter :class:`flexlib.solve.backends.sksundae.SkSundae`: no conversion per call, one shared parameter array."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps

from flexlib.compile.codegen import CompiledModel
from flexlib.solve.events import off_zero

__all__ = ["Callbacks"]


class Callbacks:
    """IDA callbacks on CasADi FunctionBuffers sharing one parameter array."""

    def __init__(self, model: CompiledModel, p: np.ndarray, state_rel: np.ndarray, dense: bool) -> None:
        self.p = p
        self._tr, self._tj, self._cj = np.zeros(1), np.zeros(1), np.zeros(1)
        self.bind(model)
        self.pattern = sps.csc_matrix((np.ones(len(model.jac_row)), model.jac_row, model.jac_colind),
                                      shape=(model.n, model.n))
        self.pattern.indices = self.pattern.indices.astype(np.int32)
        self.pattern.indptr = self.pattern.indptr.astype(np.int32)
        if dense:  # dense LU: evaluate the CSC nonzeros into a buffer, scatter into IDA's 2-D matrix
            self._nz = np.zeros(len(model.jac_row))
            self._rows = np.asarray(model.jac_row, dtype=np.intp)
            self._cols = np.repeat(np.arange(model.n), np.diff(model.jac_colind))
            self.jacfn = self._jacfn_dense  # type: ignore[method-assign]
        self.n_events = len(state_rel)
        if self.n_events:
            ind = model.sx_function("ind")
            t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
            pp = ca.SX.sym("p", len(p))
            z = ind(t, y, yp, pp)
            guarded = [off_zero(z[int(k)], model.relations[int(k)].strict, pp[model.n_params + int(k)])
                       for k in state_rel]
            zc = ca.Function("zc", [t, y, yp, pp], [ca.vertcat(*guarded)])
            self._zc = zc
            self._fz, self._evz = zc.buffer()
            self._tz = np.zeros(1)
            self._fz.set_arg(0, memoryview(self._tz))
            self._fz.set_arg(3, memoryview(p))

    def bind(self, model: CompiledModel) -> None:
        """(Re)bind the residual and Jacobian buffers to ``model``'s current functions: called again when
        C compiled in the background becomes ready, without restarting IDA (same values either way)."""
        res, jac = model.function("res"), model.function("jac")
        self._fr, self._evr = res.buffer()
        self._fj, self._evj = jac.buffer()
        self._fr.set_arg(0, memoryview(self._tr))
        self._fr.set_arg(3, memoryview(self.p))
        self._fj.set_arg(0, memoryview(self._tj))
        self._fj.set_arg(3, memoryview(self.p))
        self._fj.set_arg(4, memoryview(self._cj))

    @staticmethod
    def _into(buf: Any, ev: Any, tbuf: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray, out: np.ndarray) -> None:
        """Evaluate the buffered function ``(buf, ev)`` at ``(t, y, yp)`` into ``out`` (``p`` is bound already)."""
        tbuf[0] = t
        buf.set_arg(1, memoryview(y))
        buf.set_arg(2, memoryview(yp))
        buf.set_res(0, memoryview(out))
        ev()

    def resfn(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray) -> None:
        self._into(self._fr, self._evr, self._tr, t, y, yp, r)

    def jacobian_into(self, t: float, y: np.ndarray, yp: np.ndarray, cj: float, out: np.ndarray) -> None:
        """The iteration matrix's CSC nonzeros (the model's ``jac`` pattern, ``pattern``) at ``(t, y, yp)`` with
        ``cj`` into ``out``."""
        self._jac_into(t, y, yp, cj, out)

    def _jac_into(self, t: float, y: np.ndarray, yp: np.ndarray, cj: float, out: np.ndarray) -> None:
        self._tj[0] = t
        self._cj[0] = cj
        fj = self._fj
        fj.set_arg(1, memoryview(y))
        fj.set_arg(2, memoryview(yp))
        fj.set_res(0, memoryview(out))
        self._evj()

    def jacfn(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray, cj: float, JJ: np.ndarray) -> None:
        self._jac_into(t, y, yp, cj, JJ)

    def _jacfn_dense(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray, cj: float,
                     JJ: np.ndarray) -> None:
        self._jac_into(t, y, yp, cj, self._nz)
        JJ[self._rows, self._cols] = self._nz

    def eventsfn(self, t: float, y: np.ndarray, yp: np.ndarray, events: np.ndarray) -> None:
        self._into(self._fz, self._evz, self._tz, t, y, yp, events)
