/* flexlib native IDA driver: SUNDIALS IDA stepped in C, model functions evaluated in C.
 *
 * The model's residual, iteration matrix and event indicators are CasADi functions with the
 * code-generation calling convention  int f(const double** arg, double** res, long long* iw,
 * double* w, int mem)  -- either symbols of a generated library (flexlib_res / flexlib_jac) or
 * CasADi's SX virtual machine through its C API (casadi_c_eval_id, which takes the function id
 * first).  Python only sets the driver up, copies output rows and handles events.
 *
 * SUNDIALS 7.9 as bundled with scikit-sundae (no headers shipped): the prototypes below follow
 * sksundae/c_*.pxd (sunrealtype = double, sunindextype = int, SUNComm = int).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef double sunrealtype;
typedef int sunindextype;
typedef struct _SUNContext *SUNContext;
typedef struct _N_Vector *N_Vector;
typedef struct _SUNMatrix *SUNMatrix;
typedef struct _SUNLinearSolver *SUNLinearSolver;
typedef int (*IDAResFn)(sunrealtype, N_Vector, N_Vector, N_Vector, void *);
typedef int (*IDARootFn)(sunrealtype, N_Vector, N_Vector, sunrealtype *, void *);
typedef int (*IDALsJacFn)(sunrealtype, sunrealtype, N_Vector, N_Vector, N_Vector, SUNMatrix, void *, N_Vector,
                          N_Vector, N_Vector);

int SUNContext_Create(int comm, SUNContext *ctx);
int SUNContext_Free(SUNContext *ctx);
int SUNContext_ClearErrHandlers(SUNContext ctx);
N_Vector N_VNew_Serial(sunindextype n, SUNContext ctx);
void N_VDestroy(N_Vector v);
sunrealtype *N_VGetArrayPointer(N_Vector v);
SUNMatrix SUNDenseMatrix(sunindextype M, sunindextype N, SUNContext ctx);
sunrealtype **SUNDenseMatrix_Cols(SUNMatrix A);
SUNMatrix SUNSparseMatrix(sunindextype M, sunindextype N, sunindextype NNZ, int sparsetype, SUNContext ctx);
sunrealtype *SUNSparseMatrix_Data(SUNMatrix A);
sunindextype *SUNSparseMatrix_IndexValues(SUNMatrix A);
sunindextype *SUNSparseMatrix_IndexPointers(SUNMatrix A);
void SUNMatDestroy(SUNMatrix A);
SUNLinearSolver SUNLinSol_Dense(N_Vector y, SUNMatrix A, SUNContext ctx);
SUNLinearSolver SUNLinSol_SuperLUMT(N_Vector y, SUNMatrix A, int nthreads, SUNContext ctx);
int SUNLinSolFree(SUNLinearSolver LS);
SUNLinearSolver SUNLinSolNewEmpty(SUNContext ctx);
void SUNLinSolFreeEmpty(SUNLinearSolver S);
int SUNLinSolInitialize(SUNLinearSolver S);
int SUNLinSolSetup(SUNLinearSolver S, SUNMatrix A);
int SUNLinSolSolve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, sunrealtype tol);
void *IDACreate(SUNContext ctx);
int IDAInit(void *mem, IDAResFn res, sunrealtype t0, N_Vector y0, N_Vector yp0);
int IDAReInit(void *mem, sunrealtype t0, N_Vector y0, N_Vector yp0);
int IDASVtolerances(void *mem, sunrealtype rtol, N_Vector atol);
int IDASetUserData(void *mem, void *data);
int IDASetMaxNumSteps(void *mem, long int mxsteps);
int IDASetMaxStep(void *mem, sunrealtype hmax);
int IDASetStopTime(void *mem, sunrealtype tstop);
int IDASetId(void *mem, N_Vector id);
int IDASetNoInactiveRootWarn(void *mem);
int IDARootInit(void *mem, int nrtfn, IDARootFn g);
int IDASolve(void *mem, sunrealtype tout, sunrealtype *tret, N_Vector yret, N_Vector ypret, int itask);
int IDAGetDky(void *mem, sunrealtype t, int k, N_Vector dky);
int IDAGetRootInfo(void *mem, int *rootsfound);
int IDAGetErrWeights(void *mem, N_Vector eweight);
int IDAGetEstLocalErrors(void *mem, N_Vector ele);
int IDAGetLastStep(void *mem, sunrealtype *hlast);
int IDAGetCurrentStep(void *mem, sunrealtype *hcur);
char *IDAGetReturnFlagName(long int flag);
int IDASetLinearSolver(void *mem, SUNLinearSolver LS, SUNMatrix A);
int IDASetJacFn(void *mem, IDALsJacFn jac);
int IDASetDeltaCjLSetup(void *mem, sunrealtype dcj);
int IDASetMaxNonlinIters(void *mem, int maxcor);
int IDASetNonlinConvCoef(void *mem, sunrealtype epcon);
int IDASetMaxOrd(void *mem, int maxord);
int IDACalcIC(void *mem, int icopt, sunrealtype tout1);
int IDAGetConsistentIC(void *mem, N_Vector yy0, N_Vector yp0);
int IDAGetNumLinSolvSetups(void *mem, long int *nlinsetups);
int IDAGetNumNonlinSolvIters(void *mem, long int *nniters);
int IDAGetNumNonlinSolvConvFails(void *mem, long int *nncfails);
int IDAGetNumErrTestFails(void *mem, long int *netfails);
void IDAFree(void **mem);

#define IDA_NORMAL 1
#define IDA_ONE_STEP 2
#define IDA_TSTOP_RETURN 1
#define IDA_ROOT_RETURN 2
#define CSC_MAT 0

/* return codes of fd_advance (>= 0); IDA errors are returned as they are (< 0) */
#define FD_TSTOP 0   /* reached t_stop */
#define FD_FULL 1    /* row buffer full: copy the rows and call again */
#define FD_ROOT 2    /* a root of an event indicator */
#define FD_CHUNK 3   /* max_chunk steps done (Python polls Ctrl-C, progress, step limits) */
#define FD_TINY 4    /* more than 200 consecutive steps shorter than 1e-14 * max(1, |t|) */
#define FD_DIVERGED 5 /* fixed-step mode: the Newton corrections of a step grew or turned non-finite */

/* The generic SUNLinearSolver of SUNDIALS 7.9 (sundials_linearsolver.h; the bundled build has one more pointer
 * between content and ops, checked in ls_create), so that the driver can wrap the bundled solvers (timing) and
 * add KLU (SuiteSparse), which the bundled SUNDIALS lacks. */
typedef int (*ls_fn_t)(void);
struct ls_ops {
    int (*gettype)(SUNLinearSolver);
    int (*getid)(SUNLinearSolver);
    ls_fn_t setatimes, setpreconditioner, setscalingvectors, setoptions, setzeroguess;
    int (*initialize)(SUNLinearSolver);
    int (*setup)(SUNLinearSolver, SUNMatrix);
    int (*solve)(SUNLinearSolver, SUNMatrix, N_Vector, N_Vector, sunrealtype);
    ls_fn_t numiters, resnorm;
    sunindextype (*lastflag)(SUNLinearSolver);
    ls_fn_t space, resid;
    int (*free)(SUNLinearSolver);
};
struct _SUNLinearSolver {
    void *content;
    void *python;
    struct ls_ops *ops;
    SUNContext sunctx;
};
#define SUNLINEARSOLVER_DIRECT 0
#define SUNLINEARSOLVER_CUSTOM 17
#define SUNLS_PACKAGE_FAIL_REC 806

/* KLU (SuiteSparse) as found at run time (a shared library located by Python; NULL entries: not available).
 * klu_common of KLU 1.x/2.x (int version): the fields the driver reads are checked against klu_defaults. */
typedef struct {
    double tol, memgrow, initmem_amd, initmem, maxwork;
    int btf, ordering, scale;
    void *user_order, *user_data;
    int halt_if_singular, status, nrealloc, structural_rank, numerical_rank, singular_col, noffdiag;
    double flops, rcond, condest, rgrowth, work;
    size_t memusage, mempeak;
    char reserve[256]; /* room for fields of newer versions */
} klu_common_t;
static struct {
    int (*defaults)(klu_common_t *);
    void *(*analyze)(int, int *, int *, klu_common_t *);
    void *(*factor)(int *, int *, double *, void *, klu_common_t *);
    int (*solve)(void *, void *, int, int, double *, klu_common_t *);
    int (*free_symbolic)(void **, klu_common_t *);
    int (*free_numeric)(void **, klu_common_t *);
    int (*refactor)(int *, int *, double *, void *, void *, klu_common_t *);
    int (*rcond)(void *, void *, klu_common_t *);
} KLU;
static int klu_reuse_min_n = 0; /* refactorise with the previous pivots from this many unknowns (0: never) ... */
static double klu_rcond_min = 1e-3; /* ... while rcond stays above this share of the last full factorisation's */
/* ... and in fixed-step mode, where a full factorisation inside a step is what bounds a real-time step's cost (the
 * flexible pump truck: 3.3 ms against 0.6 ms for a refactorisation): KLU's estimate (the smallest over the largest
 * pivot) falls by more than 1e-3 when a valve path closes without the pivots going bad. At 1e-10 the flexible
 * pump truck's expand-fold at 1 ms took 1 full factorisation instead of 11, with the same steps taken unconverged
 * (18) and the same deviation from IDA (2.16 golden tolerances); each step's Newton test still checks the
 * corrections. */
static const double klu_rcond_min_fixed = 1e-10;

typedef int (*cfun_t)(const double **, double **, long long *, double *, int);
typedef int (*cidfun_t)(int, const double **, double **, long long *, double *, int);

typedef struct {
    cfun_t f;      /* generated symbol, or NULL */
    cidfun_t fid;  /* casadi_c_eval_id when f is NULL */
    int id, mem;
    const double **arg;
    double **res;
    long long *iw;
    double *w;
    double seconds;
    long calls;
} fun_t;

typedef struct {
    SUNContext ctx;
    void *mem;
    N_Vector y, yp, idv, atol, tmp;
    SUNMatrix A;
    SUNLinearSolver LS;
    int n, nnz, dense, nroot;
    int *colind, *row;
    double *jnz;
    double *p;
    double tbuf, cjbuf;
    fun_t res, jac, zc;
    /* output grid (owned by the caller) and position */
    const double *grid;
    int ngrid, kgrid;
    double tcur, tlast_row;
    int pending_step; /* rows of the last step still to be written (buffer was full) */
    int pending_flag;
    long steps;
    int tiny;
    int *rootsfound;
    double sec_advance;
    int nonfinite;
    double t_limit, h_min; /* fd_advance also returns FD_CHUNK after a step ending at or after t_limit, or
                              shorter than h_min (the state-selection monitor's schedule) */
    double hlast;          /* size of the last step taken */
    double wall_chunk;     /* fd_advance returns FD_CHUNK after this many seconds of wall time (0: no limit), so
                              that Ctrl-C/SIGTERM and the progress bar reach Python promptly on slow models */
    /* linear solver: LS is the wrapper IDA sees (ls_*), inner the bundled solver it times (dense, SuperLU_MT) */
    int linsol;            /* LS_DENSE, LS_SUPERLUMT or LS_KLU */
    SUNLinearSolver inner;
    klu_common_t klu;
    void *klu_sym, *klu_num;
    double klu_rcond_full;
    int klu_reuse;
    long ls_setups, ls_solves, ls_full; /* setups, solves, KLU numeric factorisations */
    double sec_setup, sec_solve, sec_full; /* ... and of the full KLU factorisations among the setups */
    int ls_flag;
    long nni_before, ncf_before, netf_before; /* IDA's Newton iterations, convergence and error test failures before
                                                  the last IDAReInit (which resets IDA's counters) */
    struct fixed_s *fx;    /* fixed-step mode (fd_set_fixed_step), or NULL: IDA steps */
} drv_t;

#define LS_DENSE 0
#define LS_SUPERLUMT 1
#define LS_KLU 2

static clockid_t CLOCK = CLOCK_MONOTONIC;

/* Time the driver's parts (fd_stats seconds) in thread CPU time instead of wall time (benchmarks on a shared
 * machine; a system call per reading, about 0.3 us, instead of the vDSO's 20 ns). Process-wide. */
void fd_use_cpu_clock(int on) { CLOCK = on ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC; }

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int fcall(fun_t *f) {
    double t0 = now();
    int flag = f->f ? f->f(f->arg, f->res, f->iw, f->w, f->mem) : f->fid(f->id, f->arg, f->res, f->iw, f->w, f->mem);
    f->seconds += now() - t0;
    f->calls++;
    return flag;
}

static int fun_setup(fun_t *f, void *fptr, void *fidptr, int id, int mem, long long sz_arg, long long sz_res,
                     long long sz_iw, long long sz_w) {
    f->f = (cfun_t)fptr;
    f->fid = (cidfun_t)fidptr;
    f->id = id;
    f->mem = mem;
    f->arg = calloc(sz_arg > 6 ? sz_arg : 6, sizeof(double *));
    f->res = calloc(sz_res > 2 ? sz_res : 2, sizeof(double *));
    f->iw = calloc(sz_iw > 1 ? sz_iw : 1, sizeof(long long));
    f->w = calloc(sz_w > 1 ? sz_w : 1, sizeof(double));
    f->seconds = 0.0;
    f->calls = 0;
    return (f->arg && f->res && f->iw && f->w) ? 0 : -1;
}

static void fun_free(fun_t *f) {
    free(f->arg);
    free(f->res);
    free(f->iw);
    free(f->w);
}

static int resfn(sunrealtype t, N_Vector y, N_Vector yp, N_Vector rr, void *data) {
    drv_t *d = (drv_t *)data;
    d->tbuf = t;
    d->res.arg[0] = &d->tbuf;
    d->res.arg[1] = N_VGetArrayPointer(y);
    d->res.arg[2] = N_VGetArrayPointer(yp);
    d->res.arg[3] = d->p;
    double *r = N_VGetArrayPointer(rr);
    d->res.res[0] = r;
    if (fcall(&d->res)) return -1;
    for (int i = 0; i < d->n; i++)
        if (!isfinite(r[i])) {
            d->nonfinite++;
            return 1; /* recoverable: IDA retries with a smaller step */
        }
    return 0;
}

static int jacfn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector rr, SUNMatrix J, void *data,
                 N_Vector t1, N_Vector t2, N_Vector t3) {
    (void)rr; (void)t1; (void)t2; (void)t3;
    drv_t *d = (drv_t *)data;
    d->tbuf = t;
    d->cjbuf = cj;
    d->jac.arg[0] = &d->tbuf;
    d->jac.arg[1] = N_VGetArrayPointer(y);
    d->jac.arg[2] = N_VGetArrayPointer(yp);
    d->jac.arg[3] = d->p;
    d->jac.arg[4] = &d->cjbuf;
    if (d->dense) {
        d->jac.res[0] = d->jnz;
        if (fcall(&d->jac)) return -1;
        double **cols = SUNDenseMatrix_Cols(J);
        for (int j = 0; j < d->n; j++) {
            double *c = cols[j];
            memset(c, 0, sizeof(double) * d->n);
            for (int k = d->colind[j]; k < d->colind[j + 1]; k++) c[d->row[k]] = d->jnz[k];
        }
    } else {
        memcpy(SUNSparseMatrix_IndexPointers(J), d->colind, sizeof(int) * (d->n + 1));
        memcpy(SUNSparseMatrix_IndexValues(J), d->row, sizeof(int) * (d->nnz ? d->nnz : 1));
        d->jac.res[0] = SUNSparseMatrix_Data(J);
        if (fcall(&d->jac)) return -1;
    }
    return 0;
}

static int rootfn(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype *g, void *data) {
    drv_t *d = (drv_t *)data;
    d->tbuf = t;
    d->zc.arg[0] = &d->tbuf;
    d->zc.arg[1] = N_VGetArrayPointer(y);
    d->zc.arg[2] = N_VGetArrayPointer(yp);
    d->zc.arg[3] = d->p;
    d->zc.res[0] = g;
    return fcall(&d->zc) ? -1 : 0;
}

/* ---- linear solver wrapper: times the bundled solvers, or factorises with KLU ---- */

/* KLU: the pattern is IDA's (constant); the first setup analyses it once (BTF, then a fill-reducing ordering of each
 * block: klu_analyze), and a setup factorises with threshold partial pivoting (klu_factor, tol 0.001).
 * Below klu_reuse_min_n unknowns (fd_set_klu_reuse; Python's KLU_REUSE_MIN_UNKNOWNS) KLU keeps its defaults: AMD,
 * and fresh pivots at every setup. COLAMD there halved the factorisation on the boom proxy (190 instead of 420 us)
 * but ran a stiff bushing four-bar into 20000 steps at t = 0.017 s, and refactorising with the previous pivots
 * (klu_refactor: 112 instead of 327 us) put an rtol-1e-10 test of a small model (a force computed two ways, 1e-8 N
 * allowed) 2e-8 N off. From klu_reuse_min_n unknowns, where the factorisation dominates, the ordering is COLAMD
 * (pump truck, 150 s of expand-fold: flexible 0.42 -> 0.28 ms per setup, 18 -> 16 us per solve; rigid 60 -> 46 us)
 * and a setup refactorises with the previous pivots (klu_refactor, as SUNDIALS' own KLU module does) while klu_rcond
 * stays above klu_rcond_min times the last full factorisation's: a setup whose refactor fails or degrades the
 * pivots factorises afresh. */
static int klu_full(drv_t *d, int *Ap, int *Ai, double *Ax) {
    double t0 = now();
    if (d->klu_num) KLU.free_numeric(&d->klu_num, &d->klu);
    d->klu_num = KLU.factor(Ap, Ai, Ax, d->klu_sym, &d->klu);
    d->ls_full++;
    d->sec_full += now() - t0;
    if (!d->klu_num) return d->klu.status == 1 ? SUNLS_PACKAGE_FAIL_REC : -1; /* KLU_SINGULAR: recoverable */
    if (d->klu_reuse && KLU.rcond(d->klu_sym, d->klu_num, &d->klu)) d->klu_rcond_full = d->klu.rcond;
    return 0;
}

/* KLU's symbolic analysis of the iteration matrix's pattern (constant: the model's), once per driver. 0 or -1. */
static int klu_analyze_pattern(drv_t *d) {
    d->klu_reuse = klu_reuse_min_n > 0 && d->n >= klu_reuse_min_n;
    d->klu.ordering = d->klu_reuse ? 1 : 0; /* COLAMD on the large models, AMD (KLU's default) below */
    d->klu_sym = KLU.analyze(d->n, d->colind, d->row, &d->klu);
    return d->klu_sym ? 0 : -1;
}

static int ls_setup(SUNLinearSolver S, SUNMatrix A) {
    drv_t *d = (drv_t *)S->content;
    double t0 = now();
    int flag;
    if (d->linsol != LS_KLU) {
        flag = SUNLinSolSetup(d->inner, A);
    } else {
        int *Ap = SUNSparseMatrix_IndexPointers(A), *Ai = SUNSparseMatrix_IndexValues(A);
        double *Ax = SUNSparseMatrix_Data(A);
        if (!d->klu_sym && klu_analyze_pattern(d)) { flag = -1; goto done; }
        if (d->klu_reuse && d->klu_num && KLU.refactor(Ap, Ai, Ax, d->klu_sym, d->klu_num, &d->klu)
            && KLU.rcond(d->klu_sym, d->klu_num, &d->klu)
            && d->klu.rcond >= (d->fx ? klu_rcond_min_fixed : klu_rcond_min) * d->klu_rcond_full)
            flag = 0;
        else
            flag = klu_full(d, Ap, Ai, Ax);
    }
done:
    d->ls_setups++;
    d->sec_setup += now() - t0;
    d->ls_flag = flag;
    return flag;
}

static int ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, sunrealtype tol) {
    drv_t *d = (drv_t *)S->content;
    double t0 = now();
    int flag;
    if (d->linsol != LS_KLU) {
        flag = SUNLinSolSolve(d->inner, A, x, b, tol);
    } else {
        double *xd = N_VGetArrayPointer(x);
        memcpy(xd, N_VGetArrayPointer(b), sizeof(double) * d->n);
        flag = KLU.solve(d->klu_sym, d->klu_num, d->n, 1, xd, &d->klu) ? 0 : -1;
    }
    d->ls_solves++;
    d->sec_solve += now() - t0;
    d->ls_flag = flag;
    return flag;
}

static int ls_gettype(SUNLinearSolver S) { (void)S; return SUNLINEARSOLVER_DIRECT; }
static int ls_getid(SUNLinearSolver S) { (void)S; return SUNLINEARSOLVER_CUSTOM; }
static int ls_initialize(SUNLinearSolver S) {
    drv_t *d = (drv_t *)S->content;
    return d->linsol == LS_KLU ? 0 : SUNLinSolInitialize(d->inner);
}
static sunindextype ls_lastflag(SUNLinearSolver S) { return ((drv_t *)S->content)->ls_flag; }
static int ls_free(SUNLinearSolver S) { /* the driver frees its parts in fd_free */
    S->content = NULL;
    SUNLinSolFreeEmpty(S);
    return 0;
}

/* Hand the KLU entry points to the driver (once per process; Python locates the library). fns: defaults, analyze,
 * factor, solve, free_symbolic, free_numeric. Returns 0, or -1 when klu_defaults does not
 * fill klu_common as the layout above expects (another KLU version: KLU stays off). */
int fd_set_klu(void **fns) {
    klu_common_t c;
    memset(&c, 0, sizeof c);
    int (*defaults)(klu_common_t *) = (int (*)(klu_common_t *))fns[0];
    if (!defaults(&c) || c.tol != 0.001 || c.memgrow != 1.2 || c.btf != 1 || c.ordering != 0 || c.scale != 2
        || c.halt_if_singular != 1 || c.status != 0) return -1;
    KLU.defaults = defaults;
    KLU.analyze = (void *(*)(int, int *, int *, klu_common_t *))fns[1];
    KLU.factor = (void *(*)(int *, int *, double *, void *, klu_common_t *))fns[2];
    KLU.solve = (int (*)(void *, void *, int, int, double *, klu_common_t *))fns[3];
    KLU.free_symbolic = (int (*)(void **, klu_common_t *))fns[4];
    KLU.free_numeric = (int (*)(void **, klu_common_t *))fns[5];
    KLU.refactor = (int (*)(int *, int *, double *, void *, void *, klu_common_t *))fns[6];
    KLU.rcond = (int (*)(void *, void *, klu_common_t *))fns[7];
    return 0;
}

void fd_set_klu_reuse(int min_n, double rcond_min) {
    klu_reuse_min_n = KLU.refactor && KLU.rcond ? min_n : 0;
    klu_rcond_min = rcond_min;
}

static SUNLinearSolver ls_create(drv_t *d) {
    if (d->linsol == LS_DENSE) {
        d->A = SUNDenseMatrix(d->n, d->n, d->ctx);
        d->inner = d->A ? SUNLinSol_Dense(d->y, d->A, d->ctx) : NULL;
    } else {
        d->A = SUNSparseMatrix(d->n, d->n, d->nnz ? d->nnz : 1, CSC_MAT, d->ctx);
        if (d->linsol == LS_SUPERLUMT) {
#ifndef FD_NO_SUPERLUMT /* an exported FMU links neither SuperLU_MT nor the BLAS it needs */
            d->inner = d->A ? SUNLinSol_SuperLUMT(d->y, d->A, 1, d->ctx) : NULL;
#else
            d->inner = NULL;
#endif
        } else {
            if (!KLU.defaults || KLU.defaults(&d->klu) != 1) return NULL;
        }
    }
    if (!d->A || (d->linsol != LS_KLU && !d->inner)) return NULL;
    SUNLinearSolver S = SUNLinSolNewEmpty(d->ctx);
    if (!S) return NULL;
    if (!S->ops || S->sunctx != d->ctx || S->ops->gettype || S->ops->setup) { /* not the layout declared above */
        SUNLinSolFreeEmpty(S);
        return NULL;
    }
    S->content = d;
    S->ops->gettype = ls_gettype;
    S->ops->getid = ls_getid;
    S->ops->initialize = ls_initialize;
    S->ops->setup = ls_setup;
    S->ops->solve = ls_solve;
    S->ops->lastflag = ls_lastflag;
    S->ops->free = ls_free;
    return S;
}

void fd_free(drv_t *d);
static void fx_free(struct fixed_s *x);
static void fx_restart(struct fixed_s *x);

/* Create a driver (linsol: LS_DENSE, LS_SUPERLUMT or LS_KLU, the last after fd_set_klu). fun pointers/ids/work sizes: index 0 res, 1 jac, 2 zc (zc unused when nroot == 0).
 * Returns NULL on failure (err gets a short reason). */
drv_t *fd_create(int n, int nnz, const int *colind, const int *row, int linsol, int nroot, double *p,
                 void **fptr, void *fid, const int *ids, const int *mems, const long long *sizes, double rtol,
                 const double *atol, const double *differential, double max_step, double t0, const double *y0,
                 const double *yp0, char *err) {
    drv_t *d = calloc(1, sizeof(drv_t));
    if (!d) return NULL;
    d->n = n;
    d->nnz = nnz;
    d->dense = linsol == LS_DENSE;
    d->linsol = linsol;
    d->nroot = nroot;
    d->p = p;
    d->colind = malloc(sizeof(int) * (n + 1));
    d->row = malloc(sizeof(int) * (nnz ? nnz : 1));
    d->jnz = calloc(nnz ? nnz : 1, sizeof(double));
    d->rootsfound = calloc(nroot ? nroot : 1, sizeof(int));
    if (!d->colind || !d->row || !d->jnz || !d->rootsfound) goto fail;
    memcpy(d->colind, colind, sizeof(int) * (n + 1));
    if (nnz) memcpy(d->row, row, sizeof(int) * nnz);
    for (int k = 0; k < 3; k++) {
        if (k == 2 && nroot == 0) break;
        fun_t *f = k == 0 ? &d->res : k == 1 ? &d->jac : &d->zc;
        if (fun_setup(f, fptr[k], fid, ids[k], mems[k], sizes[4 * k], sizes[4 * k + 1], sizes[4 * k + 2],
                      sizes[4 * k + 3])) goto fail;
    }
    if (SUNContext_Create(0, &d->ctx)) { strcpy(err, "SUNContext_Create"); goto fail; }
    SUNContext_ClearErrHandlers(d->ctx); /* errors come back as flags; Python words the message */
    d->y = N_VNew_Serial(n, d->ctx);
    d->yp = N_VNew_Serial(n, d->ctx);
    d->idv = N_VNew_Serial(n, d->ctx);
    d->atol = N_VNew_Serial(n, d->ctx);
    d->tmp = N_VNew_Serial(n, d->ctx);
    if (!d->y || !d->yp || !d->idv || !d->atol || !d->tmp) { strcpy(err, "N_VNew_Serial"); goto fail; }
    memcpy(N_VGetArrayPointer(d->y), y0, sizeof(double) * n);
    memcpy(N_VGetArrayPointer(d->yp), yp0, sizeof(double) * n);
    memcpy(N_VGetArrayPointer(d->idv), differential, sizeof(double) * n);
    memcpy(N_VGetArrayPointer(d->atol), atol, sizeof(double) * n);
    d->mem = IDACreate(d->ctx);
    if (!d->mem) { strcpy(err, "IDACreate"); goto fail; }
    if (IDAInit(d->mem, resfn, t0, d->y, d->yp)) { strcpy(err, "IDAInit"); goto fail; }
    if (IDASVtolerances(d->mem, rtol, d->atol)) { strcpy(err, "IDASVtolerances"); goto fail; }
    IDASetUserData(d->mem, d);
    IDASetId(d->mem, d->idv);
    IDASetMaxNumSteps(d->mem, 100000);
    if (max_step > 0) IDASetMaxStep(d->mem, max_step);
    d->LS = ls_create(d);
    if (!d->LS) { strcpy(err, "matrix or linear solver"); goto fail; }
    if (IDASetLinearSolver(d->mem, d->LS, d->A)) { strcpy(err, "IDASetLinearSolver"); goto fail; }
    if (IDASetJacFn(d->mem, jacfn)) { strcpy(err, "IDASetJacFn"); goto fail; }
    if (nroot) {
        if (IDARootInit(d->mem, nroot, rootfn)) { strcpy(err, "IDARootInit"); goto fail; }
        IDASetNoInactiveRootWarn(d->mem);
    }
    d->tcur = t0;
    d->tlast_row = t0;
    d->t_limit = INFINITY;
    d->h_min = 0.0;
    d->wall_chunk = 0.0;
    return d;
fail:
    fd_free(d);
    return NULL;
}

void fd_free(drv_t *d) {
    if (!d) return;
    if (d->mem) IDAFree(&d->mem);
    if (d->LS) SUNLinSolFree(d->LS);
    if (d->inner) SUNLinSolFree(d->inner);
    if (d->klu_num) KLU.free_numeric(&d->klu_num, &d->klu);
    if (d->klu_sym) KLU.free_symbolic(&d->klu_sym, &d->klu);
    if (d->A) SUNMatDestroy(d->A);
    N_Vector vs[5] = {d->y, d->yp, d->idv, d->atol, d->tmp};
    for (int i = 0; i < 5; i++)
        if (vs[i]) N_VDestroy(vs[i]);
    fx_free(d->fx);
    if (d->ctx) SUNContext_Free(&d->ctx);
    fun_free(&d->res);
    fun_free(&d->jac);
    if (d->nroot) fun_free(&d->zc);
    free(d->colind);
    free(d->row);
    free(d->jnz);
    free(d->rootsfound);
    free(d);
}

/* Replace the residual and Jacobian evaluators (index 0 res, 1 jac of fptr/ids/mems/sizes, as in fd_create):
 * generated C compiled in the background replaces the SX virtual machine between two steps, without restarting
 * IDA (the same operations in the same order: the trajectory does not change).  Returns 0, or -1 (no memory;
 * the old evaluators stay). */
int fd_set_funs(drv_t *d, void **fptr, void *fid, const int *ids, const int *mems, const long long *sizes) {
    fun_t f[2];
    for (int k = 0; k < 2; k++) {
        memset(&f[k], 0, sizeof(fun_t));
        if (fun_setup(&f[k], fptr[k], fid, ids[k], mems[k], sizes[4 * k], sizes[4 * k + 1], sizes[4 * k + 2],
                      sizes[4 * k + 3])) {
            fun_free(&f[0]);
            fun_free(&f[1]);
            return -1;
        }
    }
    fun_t *old[2] = {&d->res, &d->jac};
    for (int k = 0; k < 2; k++) {
        f[k].seconds = old[k]->seconds;
        f[k].calls = old[k]->calls;
        fun_free(old[k]);
        *old[k] = f[k];
    }
    return 0;
}

static long ida_count(drv_t *d, int (*get)(void *, long int *)) {
    long v = 0;
    return get(d->mem, &v) ? 0 : v;
}

/* Restart at t0 from y0, yp0 (after an event). */
int fd_reinit(drv_t *d, double t0, const double *y0, const double *yp0) {
    d->nni_before += ida_count(d, IDAGetNumNonlinSolvIters);
    d->ncf_before += ida_count(d, IDAGetNumNonlinSolvConvFails);
    d->netf_before += ida_count(d, IDAGetNumErrTestFails);
    memcpy(N_VGetArrayPointer(d->y), y0, sizeof(double) * d->n);
    memcpy(N_VGetArrayPointer(d->yp), yp0, sizeof(double) * d->n);
    d->tcur = t0;
    d->tlast_row = t0;
    d->tiny = 0;
    d->pending_step = 0;
    if (d->fx) { /* an event changed the equations: no history, a fresh iteration matrix */
        fx_restart(d->fx);
        return 0;
    }
    return IDAReInit(d->mem, t0, d->y, d->yp);
}

/* Output grid for the following fd_advance calls (times after the current one; caller keeps it alive). */
void fd_set_grid(drv_t *d, const double *grid, int ngrid) {
    d->grid = grid;
    d->ngrid = ngrid;
    d->kgrid = 0;
}

int fd_grid_pos(drv_t *d) { return d->kgrid; }

/* Extra stop conditions of fd_advance (FD_CHUNK): a step ending at or after t_limit, or shorter than h_min
 * (INFINITY and 0 switch them off). */
void fd_set_limits(drv_t *d, double t_limit, double h_min) {
    d->t_limit = t_limit;
    d->h_min = h_min;
}

/* Wall-time bound of one fd_advance call [s] (0: none); checked after each step. */
void fd_set_wall_chunk(drv_t *d, double seconds) { d->wall_chunk = seconds; }

/* IDA's Newton/linear-solver knobs (for measurements; values <= 0 keep IDA's defaults): the relative change of cj
 * that triggers a new setup (default 0.25), Newton iterations per step (4), Newton convergence coefficient (0.33). */
int fd_set_newton(drv_t *d, double dcj, int maxcor, double epcon) {
    int f = 0;
    if (dcj > 0) f |= IDASetDeltaCjLSetup(d->mem, dcj);
    if (maxcor > 0) f |= IDASetMaxNonlinIters(d->mem, maxcor);
    if (epcon > 0) f |= IDASetNonlinConvCoef(d->mem, epcon);
    return f;
}

/* Consistent algebraic unknowns and derivatives for the differential unknowns held (IDACalcIC, IDA_YA_YDP_INIT),
 * from the current point; tout1: the first output time (sets CalcIC's trial step). 0, or IDA's flag. */
int fd_calc_ic(drv_t *d, double tout1) {
    int flag = IDAReInit(d->mem, d->tcur, d->y, d->yp);
    if (!flag) flag = IDACalcIC(d->mem, 1, tout1);
    if (!flag) flag = IDAGetConsistentIC(d->mem, d->y, d->yp);
    return flag;
}

/* Highest BDF order IDA may use (1..5). */
int fd_set_max_order(drv_t *d, int maxord) { return IDASetMaxOrd(d->mem, maxord); }

/* Size of the last step taken [s]. */
double fd_last_step(drv_t *d) { return d->hlast; }

/* Write the rows due after the step that reached d->tcur; 0 if all written, 1 if the buffer filled. */
static int write_rows(drv_t *d, double *T, double *Y, double *YP, int cap, int *nrows) {
    int n = d->n;
    if (d->grid) {
        while (d->kgrid < d->ngrid && d->grid[d->kgrid] <= d->tcur) {
            if (*nrows >= cap) return 1;
            double tq = d->grid[d->kgrid];
            double *yr = Y + (size_t)(*nrows) * n, *ypr = YP + (size_t)(*nrows) * n;
            if (tq == d->tcur) {
                memcpy(yr, N_VGetArrayPointer(d->y), sizeof(double) * n);
                memcpy(ypr, N_VGetArrayPointer(d->yp), sizeof(double) * n);
            } else {
                N_Vector v = d->tmp;
                if (IDAGetDky(d->mem, tq, 0, v)) return -1;
                memcpy(yr, N_VGetArrayPointer(v), sizeof(double) * n);
                if (IDAGetDky(d->mem, tq, 1, v)) return -1;
                memcpy(ypr, N_VGetArrayPointer(v), sizeof(double) * n);
            }
            T[*nrows] = tq;
            (*nrows)++;
            d->kgrid++;
        }
    } else if (d->tcur > d->tlast_row) {
        if (*nrows >= cap) return 1;
        T[*nrows] = d->tcur;
        memcpy(Y + (size_t)(*nrows) * n, N_VGetArrayPointer(d->y), sizeof(double) * n);
        memcpy(YP + (size_t)(*nrows) * n, N_VGetArrayPointer(d->yp), sizeof(double) * n);
        (*nrows)++;
        d->tlast_row = d->tcur;
    }
    return 0;
}


/* ---- fixed-step mode: FixedStep(h) stepped in C ----
 * The algorithm of flexlib/solve/backends/fixed_step.py (its docstring is the reference), step for step: BDF2 with
 * constant steps (implicit Euler after a start, an event or a shortened step), at most `iters` Newton corrections per
 * step with an iteration matrix kept from an earlier step until c changes or a step needed more than two corrections
 * (once per step a fresh one when the old one does not converge), a step still contracting after its corrections
 * taken and counted, one whose corrections grow reported (FD_DIVERGED). The matrix and its LU are the driver's
 * (jacfn, ls_setup: dense LU or KLU), the residual resfn, the event indicators rootfn. State events at step ends:
 * a root function whose sign disagrees with its relation's value (p[rel[j]]) is a root. Real-time pacing (optional):
 * after each step the loop sleeps until the wall clock reaches the step's simulated time (over `speed`); a step that
 * ends after it is an overrun. */
typedef struct fixed_s {
    double h, rtol;
    int bdf2, iters;
    int have_prev, lu_ok, slow, contracting;
    double c_lu;
    double told;
    double *yprev, *yold, *ypold, *base, *pred, *g;
    double *save; /* the start point (y, yp) of each halving level */
    double *wlast; /* the last weighted correction (damping of a correction that turns back) */
    int max_halvings;
    N_Vector vy, vyp, vr, vdy;
    int *rel;
    long steps, newton, unconverged, njev, overruns, halved;
    double wall_sum, wall_worst, late_worst;
    double first_unconverged; /* end time of the first step taken unconverged (NAN: none) */
    double worst_t;           /* start time of the costliest step */
    long worst_work[3];       /* the costliest step's Newton corrections, matrix evaluations, full factorisations */
    long *work;               /* steps by their work: [corrections][matrices][full factorisations] (fx_work_index) */
    int realtime, rt_started;
    double speed, rt_wall0, rt_t0;
} fixed_t;

static double mono(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The work histogram's cells: corrections 0 … FX_WORK_C − 1, matrix evaluations and full factorisations 0 … FX_WORK_M − 1
 * each (a step beyond a bound is counted in its last cell). */
#define FX_WORK_C 64
#define FX_WORK_M 8
static int fx_work_index(long corrections, long matrices, long full) {
    long c = corrections < FX_WORK_C ? corrections : FX_WORK_C - 1, m = matrices < FX_WORK_M ? matrices : FX_WORK_M - 1,
         f = full < FX_WORK_M ? full : FX_WORK_M - 1;
    return (int)((c * FX_WORK_M + m) * FX_WORK_M + f);
}

static void fx_restart(fixed_t *x) {
    x->have_prev = x->lu_ok = x->slow = x->contracting = 0;
}

static void fx_free(fixed_t *x) {
    if (!x) return;
    double *bufs[8] = {x->yprev, x->yold, x->ypold, x->base, x->pred, x->g, x->save, x->wlast};
    for (int i = 0; i < 8; i++) free(bufs[i]);
    free(x->work);
    N_Vector vs[4] = {x->vy, x->vyp, x->vr, x->vdy};
    for (int i = 0; i < 4; i++)
        if (vs[i]) N_VDestroy(vs[i]);
    free(x->rel);
    free(x);
}

/* Switch the driver to fixed steps of h [s] (bdf2: 1 BDF2, 0 implicit Euler; iters: most Newton corrections; rtol:
 * max_halvings: times a step that does not converge may be halved; rtol:
 * the Newton test's relative weight, the absolute ones IDA's; rel: p index of each root function's relation value;
 * realtime: pace the steps to the wall clock at `speed` times real time). Returns 0, or -1 (no memory). */
int fd_set_fixed_step(drv_t *d, double h, int bdf2, int iters, int max_halvings, double rtol, const int *rel,
                      int realtime, double speed) {
    fixed_t *x = calloc(1, sizeof(fixed_t));
    if (!x) return -1;
    int n = d->n;
    x->h = h;
    x->bdf2 = bdf2;
    x->iters = iters;
    x->max_halvings = max_halvings;
    x->first_unconverged = NAN;
    x->rtol = rtol;
    x->realtime = realtime;
    x->speed = speed > 0 ? speed : 1.0;
    x->yprev = malloc(sizeof(double) * n);
    x->yold = malloc(sizeof(double) * n);
    x->ypold = malloc(sizeof(double) * n);
    x->base = malloc(sizeof(double) * n);
    x->pred = malloc(sizeof(double) * n);
    x->g = malloc(sizeof(double) * (d->nroot ? d->nroot : 1));
    x->rel = malloc(sizeof(int) * (d->nroot ? d->nroot : 1));
    x->save = malloc(sizeof(double) * 2 * n * (max_halvings > 0 ? max_halvings : 1));
    x->wlast = malloc(sizeof(double) * n);
    x->work = calloc(FX_WORK_C * FX_WORK_M * FX_WORK_M, sizeof(long));
    x->vy = N_VNew_Serial(n, d->ctx);
    x->vyp = N_VNew_Serial(n, d->ctx);
    x->vr = N_VNew_Serial(n, d->ctx);
    x->vdy = N_VNew_Serial(n, d->ctx);
    if (!x->yprev || !x->yold || !x->ypold || !x->base || !x->pred || !x->g || !x->rel || !x->save || !x->wlast
        || !x->work || !x->vy || !x->vyp
        || !x->vr || !x->vdy) {
        fx_free(x);
        return -1;
    }
    if (d->nroot) memcpy(x->rel, rel, sizeof(int) * d->nroot);
    fx_free(d->fx);
    d->fx = x;
    d->hlast = h;
    /* the pattern's symbolic analysis and the first numeric factorisation (KLU's pivoting, a full factorisation) now,
     * on the matrix at the start point, not in the first step: the first step refactorises its own matrix with these
     * pivots, as any step with a fresh matrix does (its values are the same to round-off) */
    if (d->linsol == LS_KLU && !d->klu_sym && klu_analyze_pattern(d)) return -1;
    if (d->linsol == LS_KLU && d->klu_reuse && !d->klu_num
        && !jacfn(d->tcur, 1.0 / h, d->y, d->yp, x->vr, d->A, d, NULL, NULL, NULL))
        klu_full(d, SUNSparseMatrix_IndexPointers(d->A), SUNSparseMatrix_IndexValues(d->A), SUNSparseMatrix_Data(d->A));
    return 0;
}

/* At most x->iters Newton corrections of F(t1, y, c y + base) = 0 from the iterate in x->vy (the matrix evaluated and
 * factorised there first if fresh; an old one given up as soon as its rate of contraction, the last correction's
 * norm over the one before, cannot bring the norm below 1 within the corrections left). Returns 1 converged, 0 not
 * (x->contracting says whether the corrections shrank), -1 the matrix could not be evaluated or factorised; *k the
 * corrections taken. */
static int fx_corrections(drv_t *d, fixed_t *x, double t1, double c, int fresh, int *k) {
    int n = d->n;
    double *y = N_VGetArrayPointer(x->vy), *yp = N_VGetArrayPointer(x->vyp);
    double *r = N_VGetArrayPointer(x->vr), *dy = N_VGetArrayPointer(x->vdy), *atol = N_VGetArrayPointer(d->atol);
    *k = 0;
    x->contracting = 0;
    if (fresh) {
        for (int i = 0; i < n; i++) yp[i] = c * y[i] + x->base[i];
        x->njev++;
        if (jacfn(t1, c, x->vy, x->vyp, x->vr, d->A, d, NULL, NULL, NULL) || ls_setup(d->LS, d->A)) {
            x->lu_ok = 0;
            return -1;
        }
        x->lu_ok = 1;
        x->c_lu = c;
    }
    double first = INFINITY, norm = INFINITY, norm_last = 0.0;
    for (int it = 1; it <= x->iters; it++) {
        *k = it;
        for (int i = 0; i < n; i++) yp[i] = c * y[i] + x->base[i];
        x->newton++;
        if (resfn(t1, x->vy, x->vyp, x->vr, d)) return 0; /* not finite: neither converged nor contracting */
        for (int i = 0; i < n; i++) r[i] = -r[i];
        if (ls_solve(d->LS, d->A, x->vdy, x->vr, 0.0)) return 0;
        double s = 0.0, dot = 0.0;
        for (int i = 0; i < n; i++) {
            y[i] += dy[i];
            double w = dy[i] / (x->rtol * fabs(y[i]) + atol[i]);
            s += w * w;
            dot += w * x->wlast[i];
            x->wlast[i] = w;
        }
        norm = sqrt(s / n);
        if (!isfinite(norm)) return 0;
        if (norm < 1.0) return 1;
        if (!fresh && it > 1 && it < x->iters && norm * pow(norm / norm_last, x->iters - it) >= 1.0) {
            /* an old matrix whose rate of contraction cannot meet the test within the corrections left: given up
             * at once for a fresh one (not after all of them) */
            x->contracting = norm < first;
            return 0;
        }
        if (it > 1 && dot < -0.5 * norm * norm_last * n) /* the correction turns back on the last one: half of it */
            for (int i = 0; i < n; i++) y[i] -= 0.5 * dy[i];
        if (it == 1) first = norm;
        norm_last = norm;
    }
    x->contracting = x->iters == 1 || norm < first;
    return 0;
}

/* Solve the step of size h from (d->tcur, d->y, d->yp); where its corrections do not converge and depth is below
 * x->max_halvings, take it as two implicit-Euler halves instead. 1 taken (the driver's point moved), 0 not. */
static int fx_attempt(drv_t *d, fixed_t *x, double h, int bdf2, int depth) {
    int n = d->n;
    double *y = N_VGetArrayPointer(d->y), *yp = N_VGetArrayPointer(d->yp), *yi = N_VGetArrayPointer(x->vy);
    double t1 = d->tcur + h, c;
    if (bdf2) {
        c = 1.5 / h;
        for (int i = 0; i < n; i++) {
            x->base[i] = (-2.0 * y[i] + 0.5 * x->yprev[i]) / h;
            x->pred[i] = 2.0 * y[i] - x->yprev[i]; /* linear extrapolation of the last two points */
        }
    } else {
        c = 1.0 / h;
        for (int i = 0; i < n; i++) {
            x->base[i] = -y[i] / h;
            x->pred[i] = y[i] + h * yp[i];
        }
    }
    int fresh = !x->lu_ok || c != x->c_lu || x->slow;
    int k = 0, more = 0;
    memcpy(yi, x->pred, sizeof(double) * n);
    int conv = fx_corrections(d, x, t1, c, fresh, &k);
    if (conv == 0 && !fresh) { /* the old matrix does not do: once more with a fresh one */
        memcpy(yi, x->pred, sizeof(double) * n);
        conv = fx_corrections(d, x, t1, c, 1, &more);
        k += more;
    }
    x->slow = k > 2;
    if (conv != 1 && depth < x->max_halvings) {
        x->halved++;
        double t_save = d->tcur, *sy = x->save + (size_t)(2 * depth) * n, *syp = sy + n;
        memcpy(sy, y, sizeof(double) * n);
        memcpy(syp, yp, sizeof(double) * n);
        if (fx_attempt(d, x, 0.5 * h, 0, depth + 1) && fx_attempt(d, x, 0.5 * h, 0, depth + 1)) return 1;
        memcpy(y, sy, sizeof(double) * n);
        memcpy(yp, syp, sizeof(double) * n);
        d->tcur = t_save;
        return 0;
    }
    if (conv != 1) {
        x->unconverged++;
        if (isnan(x->first_unconverged)) x->first_unconverged = t1;
    }
    /* a real-time step ends after its corrections: taken while they contract, the run fails where they do not */
    int ok = conv == 1 || (conv == 0 && x->contracting);
    for (int i = 0; ok && i < n; i++)
        if (!isfinite(yi[i])) ok = 0;
    if (ok) {
        for (int i = 0; i < n; i++) {
            y[i] = yi[i];
            yp[i] = c * yi[i] + x->base[i];
        }
        d->tcur = t1;
    }
    return ok;
}

/* One step of size h from (d->tcur, d->y, d->yp) (fx_attempt, ending exactly at t + h); 1 taken, 0 not. */
static int fx_step(drv_t *d, fixed_t *x, double h, int bdf2) {
    long newton0 = x->newton, njev0 = x->njev, full0 = d->ls_full;
    double w0 = now(), t_end = d->tcur + h;
    int ok = fx_attempt(d, x, h, bdf2, 0);
    if (ok) d->tcur = t_end;
    x->steps++;
    double w = now() - w0;
    long dc = x->newton - newton0, dm = x->njev - njev0, df = d->ls_full - full0;
    x->work[fx_work_index(dc, dm, df)]++;
    x->wall_sum += w;
    if (w > x->wall_worst) {
        x->wall_worst = w;
        x->worst_t = t_end - h;
        x->worst_work[0] = dc;
        x->worst_work[1] = dm;
        x->worst_work[2] = df;
    }
    return ok;
}

/* The rows due after the step from (x->told, yold, ypold) to (d->tcur, y, yp): every step, or the grid times it
 * passes (linear interpolation). 0 all written, 1 the buffer filled (called again with the next buffer). */
static int fx_write_rows(drv_t *d, fixed_t *x, double *T, double *Y, double *YP, int cap, int *nrows) {
    int n = d->n;
    double *y = N_VGetArrayPointer(d->y), *yp = N_VGetArrayPointer(d->yp);
    if (!d->grid) {
        if (d->tcur > d->tlast_row) {
            if (*nrows >= cap) return 1;
            T[*nrows] = d->tcur;
            memcpy(Y + (size_t)(*nrows) * n, y, sizeof(double) * n);
            memcpy(YP + (size_t)(*nrows) * n, yp, sizeof(double) * n);
            (*nrows)++;
            d->tlast_row = d->tcur;
        }
        return 0;
    }
    while (d->kgrid < d->ngrid && d->grid[d->kgrid] <= d->tcur) {
        double tg = d->grid[d->kgrid];
        if (tg > x->told) {
            if (*nrows >= cap) return 1;
            double s = (tg - x->told) / (d->tcur - x->told);
            double *yr = Y + (size_t)(*nrows) * n, *ypr = YP + (size_t)(*nrows) * n;
            for (int i = 0; i < n; i++) {
                yr[i] = (1.0 - s) * x->yold[i] + s * y[i];
                ypr[i] = (1.0 - s) * x->ypold[i] + s * yp[i];
            }
            T[*nrows] = tg;
            (*nrows)++;
        }
        d->kgrid++;
    }
    return 0;
}

/* The state relations whose value differs at the step's end from the one the step was taken with (rootsfound: +1
 * now true, -1 now false, 0 unchanged); 1 if any. */
static int fx_roots(drv_t *d, fixed_t *x) {
    if (!d->nroot) return 0;
    rootfn(d->tcur, d->y, d->yp, x->g, d);
    int any = 0;
    for (int j = 0; j < d->nroot; j++) {
        int now_true = x->g[j] > 0.0, was_true = d->p[x->rel[j]] != 0.0;
        d->rootsfound[j] = now_true == was_true ? 0 : now_true ? 1 : -1;
        any |= d->rootsfound[j] != 0;
    }
    return any;
}

/* Sleep until the wall clock reaches the simulated time d->tcur (real-time pacing); a step that ends after it is an
 * overrun (counted, the worst lateness kept). */
static void fx_pace(drv_t *d, fixed_t *x) {
    if (!x->realtime) return;
    double t = mono();
    if (!x->rt_started) {
        x->rt_started = 1;
        x->rt_wall0 = t;
        x->rt_t0 = d->tcur;
        return;
    }
    double due = x->rt_wall0 + (d->tcur - x->rt_t0) / x->speed;
    if (t > due) {
        x->overruns++;
        if (t - due > x->late_worst) x->late_worst = t - due;
        return;
    }
    struct timespec ts;
    ts.tv_sec = (time_t)due;
    ts.tv_nsec = (long)((due - (double)ts.tv_sec) * 1e9);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) != 0) {
    }
}

static int fx_advance(drv_t *d, double t_stop, long max_chunk, double *T, double *Y, double *YP, int cap,
                      int *nrows, long *steps_out) {
    fixed_t *x = d->fx;
    double w0 = now();
    long steps = 0;
    *nrows = 0;
    if (d->pending_step) { /* the previous call filled the buffer within one step */
        if (fx_write_rows(d, x, T, Y, YP, cap, nrows)) { *steps_out = 0; return FD_FULL; }
        d->pending_step = 0;
        if (d->pending_flag != -1000) { *steps_out = 0; return d->pending_flag; }
    }
    if (x->realtime && !x->rt_started) fx_pace(d, x);
    for (;;) {
        if (d->tcur >= t_stop) { *steps_out = steps; return FD_TSTOP; }
        double h = x->h;
        int landing = d->tcur + h >= t_stop - 1e-9 * h;
        int shortened = landing && t_stop - d->tcur < h * (1.0 - 1e-9); /* a whole step keeps its size */
        if (shortened) h = t_stop - d->tcur;
        int bdf2 = x->bdf2 && x->have_prev && !shortened;
        x->told = d->tcur;
        memcpy(x->yold, N_VGetArrayPointer(d->y), sizeof(double) * d->n);
        memcpy(x->ypold, N_VGetArrayPointer(d->yp), sizeof(double) * d->n);
        int ok = fx_step(d, x, h, bdf2);
        steps++;
        d->steps++;
        if (ok) {
            memcpy(x->yprev, x->yold, sizeof(double) * d->n); /* the point before the step is BDF2's history */
            x->have_prev = !shortened;
            d->hlast = h;
            if (landing) d->tcur = t_stop; /* a whole step ends on t_stop up to round-off */
        }
        int next = !ok ? FD_DIVERGED : fx_roots(d, x) ? FD_ROOT : landing ? FD_TSTOP : -1000;
        if (ok) fx_pace(d, x);
        if (next == -1000 && (steps >= max_chunk || d->tcur >= d->t_limit
                              || (d->wall_chunk > 0.0 && now() - w0 > d->wall_chunk)))
            next = FD_CHUNK;
        if (fx_write_rows(d, x, T, Y, YP, cap, nrows)) {
            d->pending_step = 1;
            d->pending_flag = next;
            *steps_out = steps;
            return FD_FULL;
        }
        if (next != -1000) { *steps_out = steps; return next; }
        if (*nrows >= cap) { *steps_out = steps; return FD_FULL; }
    }
}

/* Fixed-step counters: [steps, Newton corrections, unconverged steps, matrix evaluations, overruns, halved steps,
 * the costliest step's Newton corrections, matrix evaluations and full factorisations];
 * seconds: [sum of step costs, worst step cost, worst lateness behind the wall clock, end of the first unconverged
 * step (NAN: none), start of the costliest step, full KLU factorisations]; work (may be NULL): the steps by their work,
 * FX_WORK_C x FX_WORK_M x FX_WORK_M cells (fx_work_index). */
void fd_fixed_stats(drv_t *d, long *counts, double *seconds, long *work) {
    fixed_t *x = d->fx;
    if (!x) return;
    counts[0] = x->steps;
    counts[1] = x->newton;
    counts[2] = x->unconverged;
    counts[3] = x->njev;
    counts[4] = x->overruns;
    counts[5] = x->halved;
    for (int i = 0; i < 3; i++) counts[6 + i] = x->worst_work[i];
    seconds[0] = x->wall_sum;
    seconds[1] = x->wall_worst;
    seconds[2] = x->late_worst;
    seconds[3] = x->first_unconverged;
    seconds[4] = x->worst_t;
    seconds[5] = d->sec_full;
    if (work) memcpy(work, x->work, sizeof(long) * FX_WORK_C * FX_WORK_M * FX_WORK_M);
}

/* Integrate towards t_stop one internal step at a time, writing output rows into T (cap), Y, YP
 * (cap x n, row-major).  Returns FD_* (>= 0) or the IDA error flag (< 0); *nrows rows written,
 * *t_now the solver time, y_now/yp_now (n each) its solution there.  The last step's solution
 * stays readable through fd_state until the next call. */
int fd_advance(drv_t *d, double t_stop, long max_chunk, double *T, double *Y, double *YP, int cap, int *nrows,
               double *t_now, long *steps_done) {
    double w0 = now();
    int code;
    *nrows = 0;
    long steps = 0;
    if (d->fx) {
        code = fx_advance(d, t_stop, max_chunk, T, Y, YP, cap, nrows, &steps);
        goto done;
    }
    if (d->pending_step) { /* the previous call filled the buffer within one step */
        int w = write_rows(d, T, Y, YP, cap, nrows);
        if (w == 1) { code = FD_FULL; goto done; }
        if (w < 0) { code = -27; goto done; }
        d->pending_step = 0;
        if (d->pending_flag != -1000) { code = d->pending_flag; goto done; }
    }
    if (d->tcur >= t_stop) { code = FD_TSTOP; goto done; }
    IDASetStopTime(d->mem, t_stop);
    for (;;) {
        double tret = d->tcur;
        double tprev = d->tcur;
        int flag = IDASolve(d->mem, t_stop, &tret, d->y, d->yp, IDA_ONE_STEP);
        if (flag < 0) { code = flag; goto done; }
        steps++;
        d->steps++;
        d->tcur = tret;
        d->tiny = (tret - tprev <= 1e-14 * fmax(1.0, fabs(tret))) ? d->tiny + 1 : 0;
        d->hlast = tret - tprev;
        int limit = tret >= d->t_limit || (d->hlast > 0.0 && d->hlast < d->h_min)
                    || (d->wall_chunk > 0.0 && now() - w0 > d->wall_chunk);
        int next = flag == IDA_ROOT_RETURN ? FD_ROOT : flag == IDA_TSTOP_RETURN ? FD_TSTOP
                 : d->tiny > 200 ? FD_TINY : (steps >= max_chunk || limit) ? FD_CHUNK : -1000;
        if (flag == IDA_ROOT_RETURN) IDAGetRootInfo(d->mem, d->rootsfound);
        int w = write_rows(d, T, Y, YP, cap, nrows);
        if (w < 0) { code = -27; goto done; }
        if (w == 1) {
            d->pending_step = 1;
            d->pending_flag = next;
            code = FD_FULL;
            goto done;
        }
        if (next != -1000) { code = next; goto done; }
        if (*nrows >= cap) { code = FD_FULL; goto done; }
    }
done:
    *t_now = d->tcur;
    *steps_done = steps;
    d->sec_advance += now() - w0;
    return code;
}

/* The solver's current solution (at the last step or root). */
void fd_state(drv_t *d, double *y, double *yp) {
    memcpy(y, N_VGetArrayPointer(d->y), sizeof(double) * d->n);
    memcpy(yp, N_VGetArrayPointer(d->yp), sizeof(double) * d->n);
}

void fd_roots(drv_t *d, int *out) { memcpy(out, d->rootsfound, sizeof(int) * (d->nroot ? d->nroot : 1)); }

/* Error weights and IDA's estimated local errors of the last step (diagnostics). */
int fd_diagnostics(drv_t *d, double *ewt, double *ele) {
    int f1 = IDAGetErrWeights(d->mem, d->tmp);
    memcpy(ewt, N_VGetArrayPointer(d->tmp), sizeof(double) * d->n);
    int f2 = IDAGetEstLocalErrors(d->mem, d->tmp);
    memcpy(ele, N_VGetArrayPointer(d->tmp), sizeof(double) * d->n);
    return f1 ? f1 : f2;
}

/* counters: [res calls, jac calls, root calls, steps, non-finite residuals, linear solver setups, solves, full KLU
 * factorisations, Newton iterations, Newton convergence failures, error test failures];
 * seconds: [res, jac, root, advance, linear solver setups, solves] */
void fd_stats(drv_t *d, long *counts, double *seconds) {
    counts[5] = d->ls_setups;
    counts[6] = d->ls_solves;
    counts[7] = d->ls_full;
    counts[8] = d->nni_before + ida_count(d, IDAGetNumNonlinSolvIters);
    counts[9] = d->ncf_before + ida_count(d, IDAGetNumNonlinSolvConvFails);
    counts[10] = d->netf_before + ida_count(d, IDAGetNumErrTestFails);
    seconds[4] = d->sec_setup;
    seconds[5] = d->sec_solve;
    counts[0] = d->res.calls;
    counts[1] = d->jac.calls;
    counts[2] = d->nroot ? d->zc.calls : 0;
    counts[3] = d->steps;
    counts[4] = d->nonfinite;
    seconds[0] = d->res.seconds;
    seconds[1] = d->jac.seconds;
    seconds[2] = d->nroot ? d->zc.seconds : 0.0;
    seconds[3] = d->sec_advance;
}

/* IDA's name of a return flag (e.g. "IDA_CONV_FAIL") into buf (len bytes). */
void fd_flag_name(long flag, char *buf, int len) {
    char *s = IDAGetReturnFlagName(flag);
    if (s) {
        strncpy(buf, s, len - 1);
        buf[len - 1] = 0;
        free(s);
    } else {
        buf[0] = 0;
    }
}
