/* flexlib FMI 2.0 co-simulation unit: the model's generated C (model.c), the fixed-step stepper of the ida-native
 * driver (ida_driver.c, included: its "fixed-step mode") and this file, which implements the FMI 2.0 co-simulation
 * interface on them. fmu_data.h (written by flexlib.fmi.export) holds the model's sizes, the consistent start, the
 * parameter vector, the stepper's settings and the variable table.
 *
 * The FMI 2.0 types and functions below are declared from the standard's text (FMI 2.0.4, sections 2.1 and 4.2);
 * no header of the standard is needed to compile the unit.
 *
 * Value references: 0 ... NVAR-1 index the variable table: VAR_KIND[k] 0 = an entry of the parameter vector p
 * (parameters, and top-level inputs, which are parameters a master may set between steps), 1 = an output computed
 * by flexlib_out from (t, y, y', p).
 */
#define FD_NO_SUPERLUMT
#include "ida_driver.c"

#include <stdarg.h>
#include <stdio.h>

#include "fmu_data.h"

typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef char fmi2Byte;
#define fmi2True 1
#define fmi2False 0
typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum { fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime, fmi2Terminated } fmi2StatusKind;
typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String, ...);
typedef void *(*fmi2CallbackAllocateMemory)(size_t, size_t);
typedef void (*fmi2CallbackFreeMemory)(void *);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment, fmi2Status);
typedef struct {
    const fmi2CallbackLogger logger;
    const fmi2CallbackAllocateMemory allocateMemory;
    const fmi2CallbackFreeMemory freeMemory;
    const fmi2StepFinished stepFinished;
    const fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

#define EXPORT __attribute__((visibility("default")))

typedef int (*casadi_fun)(const double **, double **, long long *, double *, int);
typedef int (*casadi_work)(long long *, long long *, long long *, long long *);

extern int flexlib_res(const double **, double **, long long *, double *, int);
extern int flexlib_res_work(long long *, long long *, long long *, long long *);
extern int flexlib_jac(const double **, double **, long long *, double *, int);
extern int flexlib_jac_work(long long *, long long *, long long *, long long *);
extern int flexlib_zc(const double **, double **, long long *, double *, int);
extern int flexlib_zc_work(long long *, long long *, long long *, long long *);
extern int flexlib_out(const double **, double **, long long *, double *, int);
extern int flexlib_out_work(long long *, long long *, long long *, long long *);
extern int flexlib_tev(const double **, double **, long long *, double *, int);
extern int flexlib_tev_work(long long *, long long *, long long *, long long *);

#if FMU_KLU
int klu_defaults(void *);
void *klu_analyze(int, int *, int *, void *);
void *klu_factor(int *, int *, double *, void *, void *);
int klu_solve(void *, void *, int, int, double *, void *);
int klu_free_symbolic(void **, void *);
int klu_free_numeric(void **, void *);
int klu_refactor(int *, int *, double *, void *, void *, void *);
int klu_rcond(void *, void *, void *);
#endif

typedef struct {
    fmi2String name;
    fmi2CallbackFunctions cb;
    int logging;
    drv_t *drv;
    double p[NP_ALL];       /* parameters and top-level inputs, then the relation values */
    double t;               /* the time reached */
    double t_start, t_stop;
    int initialised, changed, terminated;
    int inputs_changed; /* an input set since the last step: an event (a restart) before the next one */
    double out[NOUT > 0 ? NOUT : 1];
    int out_valid;
    fun_t outf, tevf;
    double ta[NTIME + 1], tb[NTIME + 1]; /* time event relations: a·t + b */
    double grid[1];
} instance_t;

static void say(instance_t *c, fmi2Status status, const char *category, const char *fmt, ...) {
    if (!c->cb.logger) return;
    if (status == fmi2OK && !c->logging) return;
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    c->cb.logger(c->cb.componentEnvironment, c->name, status, category, "%s", buf);
}

EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
EXPORT const char *fmi2GetVersion(void) { return "2.0"; }

EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean on, size_t n, const fmi2String cats[]) {
    (void)n; (void)cats;
    ((instance_t *)comp)->logging = on;
    return fmi2OK;
}

static int make_driver(instance_t *c) {
    void *fptr[3] = {(void *)flexlib_res, (void *)flexlib_jac, (void *)flexlib_zc};
    casadi_work works[3] = {flexlib_res_work, flexlib_jac_work, flexlib_zc_work};
    long long sizes[12];
    int ids[3] = {0, 0, 0}, mems[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) works[k](&sizes[4 * k], &sizes[4 * k + 1], &sizes[4 * k + 2], &sizes[4 * k + 3]);
    char err[128] = "";
#if FMU_KLU
    void *fns[8] = {(void *)klu_defaults, (void *)klu_analyze, (void *)klu_factor, (void *)klu_solve,
                    (void *)klu_free_symbolic, (void *)klu_free_numeric, (void *)klu_refactor, (void *)klu_rcond};
    if (fd_set_klu(fns)) {
        say(c, fmi2Error, "logStatusError", "the bundled KLU library does not have the expected layout");
        return -1;
    }
    fd_set_klu_reuse(KLU_REUSE_MIN_N, KLU_REUSE_RCOND);
#endif
    c->drv = fd_create(N, NNZ, JAC_COLIND, JAC_ROW, FMU_KLU ? LS_KLU : LS_DENSE, NROOT, c->p, fptr, NULL, ids, mems,
                       sizes, RTOL, ATOL, DIFFERENTIAL, 0.0, c->t_start, Y0, YP0, err);
    if (!c->drv) {
        say(c, fmi2Error, "logStatusError", "could not set up the stepper: %s failed", err);
        return -1;
    }
    if (fd_set_fixed_step(c->drv, STEP, BDF2, NEWTON_ITERS, MAX_HALVINGS, RTOL, REL_INDEX, 0, 1.0)) {
        say(c, fmi2Error, "logStatusError", "could not set up the fixed-step mode (no memory)");
        return -1;
    }
    return 0;
}

EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                                     const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                                     fmi2Boolean logging) {
    (void)resources; (void)visible;
    instance_t *c = calloc(1, sizeof(instance_t));
    if (!c) return NULL;
    c->name = name;
    if (functions) memcpy(&c->cb, functions, sizeof(fmi2CallbackFunctions));
    c->logging = logging;
    if (type != fmi2CoSimulation) {
        say(c, fmi2Error, "logStatusError", "this unit is a co-simulation FMU (no model exchange)");
        free(c);
        return NULL;
    }
    if (!guid || strcmp(guid, FMU_GUID) != 0) {
        say(c, fmi2Error, "logStatusError", "GUID %s does not match the unit's %s", guid ? guid : "(null)", FMU_GUID);
        free(c);
        return NULL;
    }
    memcpy(c->p, P0, sizeof(double) * NP_ALL);
    c->t_start = c->t = T0;
    c->t_stop = INFINITY;
    long long sz[4];
    flexlib_out_work(&sz[0], &sz[1], &sz[2], &sz[3]);
    if (fun_setup(&c->outf, (void *)flexlib_out, NULL, 0, 0, sz[0], sz[1], sz[2], sz[3])) {
        free(c);
        return NULL;
    }
    flexlib_tev_work(&sz[0], &sz[1], &sz[2], &sz[3]);
    if (fun_setup(&c->tevf, (void *)flexlib_tev, NULL, 0, 0, sz[0], sz[1], sz[2], sz[3])) {
        fun_free(&c->outf);
        free(c);
        return NULL;
    }
    return c;
}

EXPORT void fmi2FreeInstance(fmi2Component comp) {
    instance_t *c = comp;
    if (!c) return;
    fd_free(c->drv);
    fun_free(&c->outf);
    fun_free(&c->tevf);
    free(c);
}

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean tol_defined, fmi2Real tol, fmi2Real t_start,
                                      fmi2Boolean stop_defined, fmi2Real t_stop) {
    instance_t *c = comp;
    (void)tol_defined; (void)tol;
    if (t_start != T0) {
        say(c, fmi2Error, "logStatusError", "start time %g s: the unit was exported with its consistent start at "
            "t = %g s (export again with t_start)", t_start, T0);
        return fmi2Error;
    }
    c->t_stop = stop_defined ? t_stop : INFINITY;
    return fmi2OK;
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component comp) { (void)comp; return fmi2OK; }

EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component comp) {
    instance_t *c = comp;
    if (make_driver(c)) return fmi2Error;
    if (c->changed) { /* parameters set since the export: algebraic unknowns and derivatives found again */
        int flag = fd_calc_ic(c->drv, c->t_start + STEP);
        if (flag) {
            say(c, fmi2Error, "logStatusError", "no consistent start for the parameters set (IDACalcIC flag %d)",
                flag);
            return fmi2Error;
        }
    }
    c->initialised = 1;
    c->out_valid = 0;
    return fmi2OK;
}

EXPORT fmi2Status fmi2Terminate(fmi2Component comp) { ((instance_t *)comp)->terminated = 1; return fmi2OK; }

EXPORT fmi2Status fmi2Reset(fmi2Component comp) {
    instance_t *c = comp;
    fd_free(c->drv);
    c->drv = NULL;
    memcpy(c->p, P0, sizeof(double) * NP_ALL);
    c->t = c->t_start = T0;
    c->initialised = c->changed = c->terminated = c->out_valid = 0;
    return fmi2OK;
}

static int outputs(instance_t *c) {
    if (c->out_valid || NOUT == 0) return 0;
    double y[N > 0 ? N : 1], yp[N > 0 ? N : 1];
    if (c->drv) {
        fd_state(c->drv, y, yp);
    } else {
        memcpy(y, Y0, sizeof(double) * N);
        memcpy(yp, YP0, sizeof(double) * N);
    }
    c->outf.arg[0] = &c->t;
    c->outf.arg[1] = y;
    c->outf.arg[2] = yp;
    c->outf.arg[3] = c->p;
    c->outf.res[0] = c->out;
    if (fcall(&c->outf)) return -1;
    c->out_valid = 1;
    return 0;
}

EXPORT fmi2Status fmi2GetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    instance_t *c = comp;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= NVAR) {
            say(c, fmi2Error, "logStatusError", "fmi2GetReal: no variable with value reference %u", vr[i]);
            return fmi2Error;
        }
        if (VAR_KIND[vr[i]] == 0) {
            value[i] = c->p[VAR_INDEX[vr[i]]];
        } else {
            if (outputs(c)) {
                say(c, fmi2Error, "logStatusError", "the outputs could not be evaluated at t = %g s", c->t);
                return fmi2Error;
            }
            value[i] = c->out[VAR_INDEX[vr[i]]];
        }
    }
    return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    instance_t *c = comp;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= NVAR || VAR_KIND[vr[i]] != 0) {
            say(c, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u is not a parameter or an input",
                vr[i]);
            return fmi2Error;
        }
        if (c->initialised && !VAR_INPUT[vr[i]]) {
            say(c, fmi2Error, "logStatusError", "fmi2SetReal: %s is a fixed parameter: set it before "
                "fmi2ExitInitializationMode", VAR_NAME[vr[i]]);
            return fmi2Error;
        }
        if (!isfinite(value[i])) {
            say(c, fmi2Error, "logStatusError", "fmi2SetReal: %s = %g is not finite", VAR_NAME[vr[i]], value[i]);
            return fmi2Error;
        }
        if (c->p[VAR_INDEX[vr[i]]] != value[i]) {
            if (c->initialised) c->inputs_changed = 1;
            else c->changed = 1;
        }
        c->p[VAR_INDEX[vr[i]]] = value[i];
        c->out_valid = 0;
    }
    return fmi2OK;
}

/* The event iteration at the driver's point after relation values changed (a root at a step's end, a time event):
 * the algebraic unknowns and the derivatives found again with the states held (IDACalcIC), every state relation
 * evaluated there and switched where its sign disagrees with its value, until none does (as the event iteration of a
 * flexlib run, flexlib.solve.events); then the stepper restarts from there. 0, or -1 (no consistent point, or no
 * settling in 50 passes). */
static int settle(instance_t *c) {
    drv_t *d = c->drv;
    double g[NROOT > 0 ? NROOT : 1];
    for (int pass = 0; pass < 50; pass++) {
        int flag = fd_calc_ic(d, d->tcur + STEP);
        if (flag) {
            say(c, fmi2Error, "logStatusError", "event at t = %.10g s: no consistent point with the new relation "
                "values (IDACalcIC flag %d)", d->tcur, flag);
            return -1;
        }
        int changed = 0;
        if (NROOT) {
            rootfn(d->tcur, d->y, d->yp, g, d);
            for (int j = 0; j < NROOT; j++) {
                double now_true = g[j] > 0.0 ? 1.0 : 0.0;
                if (now_true != c->p[REL_INDEX[j]]) {
                    c->p[REL_INDEX[j]] = now_true;
                    changed = 1;
                    say(c, fmi2OK, "logEvents", "t = %.10g s: relation %d -> %g (pass %d)", d->tcur, REL_INDEX[j],
                        now_true, pass);
                }
            }
        }
        if (!changed) {
            double y[N], yp[N];
            fd_state(d, y, yp);
            fd_reinit(d, d->tcur, y, yp);
            return 0;
        }
    }
    say(c, fmi2Error, "logStatusError", "event at t = %.10g s: the relations do not settle in 50 passes", d->tcur);
    return -1;
}

/* Apply the relations that switched at the step's end (FD_ROOT), then the event iteration. */
static int switch_relations(instance_t *c) {
    int found[NROOT > 0 ? NROOT : 1];
    fd_roots(c->drv, found);
    for (int j = 0; j < NROOT; j++)
        if (found[j]) {
            c->p[REL_INDEX[j]] = found[j] > 0 ? 1.0 : 0.0;
            say(c, fmi2OK, "logEvents", "t = %.10g s: root of relation %d -> %d", c->drv->tcur, REL_INDEX[j],
                found[j] > 0);
        }
    return settle(c);
}

/* The earliest time event after t (INFINITY if none): a relation a·t + b of time and parameters whose zero lies
 * there, as flexlib.solve.events.next_time_event finds it. */
static double next_time_event(instance_t *c, double t) {
    if (NTIME == 0) return INFINITY;
    c->tevf.arg[0] = c->p;
    c->tevf.res[0] = c->ta;
    c->tevf.res[1] = c->tb;
    if (fcall(&c->tevf)) return INFINITY;
    double best = INFINITY, tol = 1e-13 * fmax(1.0, fabs(t));
    for (int k = 0; k < NTIME; k++) {
        if (c->ta[k] == 0.0) continue;
        double te = -c->tb[k] / c->ta[k];
        if (te > t + tol && te < best) best = te;
    }
    return best;
}

/* At a time event te: the time relations whose zero is there take their new value (a > 0: true), and the stepper
 * restarts. */
static int time_event(instance_t *c, double te) {
    double tol = 1e-13 * fmax(1.0, fabs(te));
    for (int k = 0; k < NTIME; k++)
        if (c->ta[k] != 0.0 && fabs(-c->tb[k] / c->ta[k] - te) <= tol) c->p[TIME_INDEX[k]] = c->ta[k] > 0 ? 1.0 : 0.0;
    c->drv->tcur = te;
    return settle(c);
}

EXPORT fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real H, fmi2Boolean no_prior) {
    instance_t *c = comp;
    (void)no_prior;
    if (!c->initialised || c->terminated) {
        say(c, fmi2Error, "logStatusError", "fmi2DoStep outside the stepping mode");
        return fmi2Error;
    }
    if (fabs(t - c->t) > 1e-9 * fmax(1.0, fabs(t))) {
        say(c, fmi2Error, "logStatusError", "fmi2DoStep from t = %.10g s, but the unit is at %.10g s", t, c->t);
        return fmi2Error;
    }
    double t_end = t + H;
    c->grid[0] = t_end;
    fd_set_grid(c->drv, c->grid, 1);
    double T[1], Y[N > 0 ? N : 1], YP[N > 0 ? N : 1], t_now = t;
    int rows = 0, events = 0;
    long steps = 0;
    if (c->inputs_changed) { /* a jump of an input is an event: consistent point, relations, restart */
        c->inputs_changed = 0;
        if (settle(c)) return fmi2Error;
        fd_set_grid(c->drv, c->grid, 1);
    }
    double t_event = next_time_event(c, t);
    for (;;) {
        int code = fd_advance(c->drv, fmin(t_event, t_end), 1L << 40, T, Y, YP, 1, &rows, &t_now, &steps);
        if (code == FD_TSTOP && t_event <= t_end) { /* also a time event on the communication point */
            if (time_event(c, t_event)) return fmi2Error;
            fd_set_grid(c->drv, c->grid, 1);
            if (t_event >= t_end) break;
            t_event = next_time_event(c, t_event);
            continue;
        }
        if (code == FD_ROOT) {
            if (++events > 100 * (1 + (int)(H / STEP))) {
                say(c, fmi2Error, "logStatusError", "event chattering at t = %.10g s", t_now);
                return fmi2Error;
            }
            if (switch_relations(c)) return fmi2Error;
            fd_set_grid(c->drv, c->grid, 1);
            continue;
        }
        if (code == FD_DIVERGED) {
            say(c, fmi2Error, "logStatusError", "the Newton iteration of a fixed step diverged at t = %.10g s "
                "(export with a smaller step)", t_now);
            c->t = t_now;
            c->out_valid = 0;
            return fmi2Error;
        }
        if (code == FD_TSTOP) break;
        if (code < 0) {
            say(c, fmi2Error, "logStatusError", "the stepper failed at t = %.10g s (flag %d)", t_now, code);
            return fmi2Error;
        }
    }
    c->t = t_end;
    c->out_valid = 0;
    return fmi2OK;
}

EXPORT fmi2Status fmi2CancelStep(fmi2Component comp) { (void)comp; return fmi2Error; }

EXPORT fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value) {
    (void)comp; (void)s; (void)value;
    return fmi2Discard;
}

EXPORT fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value) {
    instance_t *c = comp;
    if (s == fmi2LastSuccessfulTime) {
        *value = c->t;
        return fmi2OK;
    }
    return fmi2Discard;
}

EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Integer *value) {
    (void)comp; (void)s; (void)value;
    return fmi2Discard;
}

EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)comp; (void)s; (void)value;
    return fmi2Discard;
}

EXPORT fmi2Status fmi2GetStringStatus(fmi2Component comp, const fmi2StatusKind s, fmi2String *value) {
    (void)comp; (void)s; (void)value;
    return fmi2Discard;
}

/* No integer, boolean or string variables; no FMU state, derivatives or input derivatives. */
static fmi2Status none(fmi2Component comp, const char *what) {
    say(comp, fmi2Error, "logStatusError", "%s is not supported by this unit", what);
    return fmi2Error;
}

EXPORT fmi2Status fmi2GetInteger(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2Integer v[]) {
    (void)vr; (void)v;
    return nvr ? none(comp, "fmi2GetInteger") : fmi2OK;
}
EXPORT fmi2Status fmi2GetBoolean(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean v[]) {
    (void)vr; (void)v;
    return nvr ? none(comp, "fmi2GetBoolean") : fmi2OK;
}
EXPORT fmi2Status fmi2GetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2String v[]) {
    (void)vr; (void)v;
    return nvr ? none(comp, "fmi2GetString") : fmi2OK;
}
EXPORT fmi2Status fmi2SetInteger(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                 const fmi2Integer v[]) {
    (void)vr; (void)v;
    return nvr ? none(comp, "fmi2SetInteger") : fmi2OK;
}
EXPORT fmi2Status fmi2SetBoolean(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                 const fmi2Boolean v[]) {
    (void)vr; (void)v;
    return nvr ? none(comp, "fmi2SetBoolean") : fmi2OK;
}
EXPORT fmi2Status fmi2SetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const fmi2String v[]) {
    (void)vr; (void)v;
    return nvr ? none(comp, "fmi2SetString") : fmi2OK;
}
EXPORT fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *s) { (void)s; return none(comp, "FMU state"); }
EXPORT fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate s) { (void)s; return none(comp, "FMU state"); }
EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *s) { (void)s; return none(comp, "FMU state"); }
EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate s, size_t *n) {
    (void)s; (void)n;
    return none(comp, "FMU state");
}
EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate s, fmi2Byte b[], size_t n) {
    (void)s; (void)b; (void)n;
    return none(comp, "FMU state");
}
EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte b[], size_t n, fmi2FMUstate *s) {
    (void)b; (void)n; (void)s;
    return none(comp, "FMU state");
}
EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference u[], size_t nu,
                                               const fmi2ValueReference z[], size_t nz, const fmi2Real du[],
                                               fmi2Real dz[]) {
    (void)u; (void)nu; (void)z; (void)nz; (void)du; (void)dz;
    return none(comp, "fmi2GetDirectionalDerivative");
}
EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                              const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return none(comp, "fmi2SetRealInputDerivatives");
}
EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                               const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return none(comp, "fmi2GetRealOutputDerivatives");
}
