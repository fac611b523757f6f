/* The checks both FMI versions make (gd_glue.h): the calls the standard forbids are refused
 * with a message, and a state is used only once it is known to be one of this FMU's, with
 * finite values inside the kernel's ranges, so that a foreign or corrupted state gives Error,
 * never an out-of-bounds read. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "gd_glue.h"

#define M (&gd_model_data)
#define D gd_drive_data

void gd_g_defaults(gd_dstate *s)
{
    if (D) gd_drive_defaults(s, M, D);
    else gd_defaults(&s->k, M);
}

void gd_g_start(gd_dstate *s, double t0)
{
    if (D) gd_drive_start(s, M, D, t0);
    else gd_start(&s->k, M, t0);
}

int gd_g_advance(gd_dstate *s, double t_end)
{
    return D ? gd_drive_advance(s, M, D, t_end) : gd_advance(&s->k, M, t_end);
}

int gd_g_get(const gd_dstate *s, const unsigned *vr, size_t n, double *v)
{
    return D ? gd_drive_get(s, M, D, vr, n, v) : gd_get(&s->k, M, vr, n, v);
}

int gd_g_read(const gd_dstate *s, int mode, const unsigned *vr, size_t n, double *v)
{
    gd_dstate start;
    if (mode != GD_INIT) return gd_g_get(s, vr, n, v);
    start = *s;   /* in initialization mode: the start state of the values set so far */
    gd_g_start(&start, s->k.t);
    return gd_g_get(&start, vr, n, v);
}

int gd_g_set(gd_dstate *s, unsigned vr, double value, int started, char *msg, size_t len)
{
    return D ? gd_drive_set(s, D, vr, value, started, msg, len)
             : gd_set(&s->k, M, vr, value, started, msg, len);
}

int gd_token_ok(const char *token)
{
    return token != NULL && strcmp(token, gd_instantiation_token) == 0;
}

int gd_check_step(int mode, const gd_state *s, double t, double h, const char *fn, char *msg,
                  size_t len)
{
    /* a host that forms its communication points as k h rather than by adding h differs from
     * the FMU's t + h by rounding: a few ulp of t are taken as the FMU's time */
    double slack = 16.0 * DBL_EPSILON * fmax(fabs(t), fabs(s->t));
    if (mode != GD_STEP) {
        snprintf(msg, len, "%s: called %s; doStep is allowed only after "
                 "ExitInitializationMode and before Terminate", fn,
                 mode == GD_TERMINATED ? "after Terminate" : "before initialization");
        return GD_ERR_STEP;
    }
    if (!(h > 0.0) || !(h <= DBL_MAX)) {
        snprintf(msg, len, "%s: communicationStepSize = %g s: it must be positive and finite",
                 fn, h);
        return GD_ERR_STEP;
    }
    if (!(fabs(t - s->t) <= slack)) {
        snprintf(msg, len, "%s: currentCommunicationPoint = %.17g s, but the FMU is at "
                 "t = %.17g s: a step starts where the last one ended (or restore a state "
                 "with SetFMUstate)", fn, t, s->t);
        return GD_ERR_STEP;
    }
    return GD_OK;
}

void gd_save(const gd_dstate *s, int mode, gd_saved *out)
{
    memset(out, 0, sizeof *out);
    out->magic = GD_STATE_MAGIC;
    out->version = GD_STATE_VERSION;
    out->size = (unsigned)sizeof *out;
    strncpy(out->token, gd_instantiation_token, GD_TOKEN_SIZE - 1);
    out->mode = mode;
    out->st = *s;
}

static int real_ok(double v) { return v == v && fabs(v) <= DBL_MAX; }

int gd_check_saved(const void *b, size_t size, const gd_model *m, const char *fn,
                   gd_dstate *out, int *mode, char *msg, size_t len)
{
    gd_saved sv;
    const gd_state *s = &sv.st.k;
    const char *bad = NULL;
    int j;
    if (b == NULL || size != sizeof sv) {
        snprintf(msg, len, "%s: refused: a state of %lu bytes, this FMU's are %lu bytes", fn,
                 (unsigned long)(b ? size : 0), (unsigned long)sizeof sv);
        return GD_ERR_VR;
    }
    memcpy(&sv, b, sizeof sv);   /* b may be unaligned (serialized bytes) */
    if (sv.magic != GD_STATE_MAGIC || sv.size != sizeof sv)
        bad = "not a gear_dyn FMU state (wrong magic number or size)";
    else if (sv.version != GD_STATE_VERSION)
        bad = "a gear_dyn FMU state of another format version";
    else if (memchr(sv.token, 0, GD_TOKEN_SIZE) == NULL || !gd_token_ok(sv.token))
        bad = "the state of another FMU (its instantiation token is not this FMU's)";
    else if (sv.mode < GD_INSTANTIATED || sv.mode > GD_TERMINATED)
        bad = "its instance mode is out of range";
    else if (!real_ok(s->t) || !real_ok(s->x) || !real_ok(s->v) || !real_ok(s->frac)
             || !real_ok(s->h) || s->h < 0.0)
        bad = "non-finite time, state or step size";
    else if (s->piece < 0 || s->piece >= m->n_pieces || !(s->frac >= m->breaks[s->piece])
             || !(s->frac <= m->breaks[s->piece + 1]))
        bad = "its table piece or mesh phase is outside the table";
    else if (s->regime < -1 || s->regime > 1 || s->n_events < 0)
        bad = "its contact regime or event count is out of range";
    for (j = 0; !bad && j < 4; j++)
        if (!real_ok(s->q[j])) bad = "non-finite torsional state";
    for (j = 0; !bad && j < GD_NPAR; j++) {
        const gd_param *p = &m->params[j];
        double v = s->par[j];
        if (!(v >= p->low && v <= p->high) || (p->low_open && v == p->low))
            bad = "a parameter or input out of its range";
    }
    for (j = 0; !bad && j < GV_NPAR; j++) {   /* the drivetrain's (zero, unused, without) */
        const gd_param *p = D ? &D->params[j] : NULL;
        double v = sv.st.par[j];
        if (p ? !(v >= p->low && v <= p->high) || (p->low_open && v == p->low) : v != 0.0)
            bad = "a parameter or input out of its range";
    }
    if (bad) {
        snprintf(msg, len, "%s: refused: %s", fn, bad);
        return GD_ERR_VR;
    }
    if (out) *out = sv.st;
    if (mode) *mode = sv.mode;
    return GD_OK;
}
