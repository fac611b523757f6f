/* What the FMI 2.0 and 3.0 glue (gd_fmi2.c, gd_fmi3.c) share: the instance's mode, the checks
 * of a doStep call and the FMU state as saved, serialized and validated (gd_glue.c). */
#ifndef GD_GLUE_H
#define GD_GLUE_H

#include <stddef.h>
#include "gd_drive.h"

/* the instantiation token (FMI 2 guid) of this FMU, as in its modelDescription (model_data.c) */
extern const char gd_instantiation_token[];

/* the instance's mode: doStep only in GD_STEP */
enum { GD_INSTANTIATED, GD_INIT, GD_STEP, GD_TERMINATED };

#define GD_STATE_MAGIC 0x67645354u   /* "gdST" */
#define GD_STATE_VERSION 1u
#define GD_TOKEN_SIZE 48

/* an FMU state (fmi2FMUstate / fmi3FMUState) and its serialized bytes: a header that names
 * the FMU it belongs to, then the kernel's state */
typedef struct {
    unsigned magic, version, size;   /* GD_STATE_MAGIC, GD_STATE_VERSION, sizeof(gd_saved) */
    char token[GD_TOKEN_SIZE];       /* gd_instantiation_token, zero padded */
    int mode;                        /* the instance's mode when saved */
    gd_dstate st;
} gd_saved;

/* 1 if token is this FMU's instantiation token */
int gd_token_ok(const char *token);
/* GD_OK, or GD_ERR_STEP with a message naming fn: doStep(t, h) in mode `mode` from state s */
int gd_check_step(int mode, const gd_state *s, double t, double h, const char *fn, char *msg,
                  size_t len);
/* the model calls of the glue: the pinion-speed interface (the kernel's gd_start, ...) or,
 * where gd_drive_data is not NULL, the drivetrain interface (gd_drive_start, ...) */
void gd_g_defaults(gd_dstate *s);
void gd_g_start(gd_dstate *s, double t0);
int gd_g_advance(gd_dstate *s, double t_end);
int gd_g_get(const gd_dstate *s, const unsigned *vr, size_t n, double *v);
/* gd_g_get as an FMI getter answers in mode `mode`: in initialization mode the values of the
 * start state that ExitInitializationMode will make of the values set so far */
int gd_g_read(const gd_dstate *s, int mode, const unsigned *vr, size_t n, double *v);
int gd_g_set(gd_dstate *s, unsigned vr, double value, int started, char *msg, size_t len);

/* the saved form of s in mode `mode` */
void gd_save(const gd_dstate *s, int mode, gd_saved *out);
/* GD_OK if the size bytes at b are a valid saved state of this FMU (then copied into out and
 * its mode into *mode, where not NULL), else GD_ERR_VR with a message naming fn and what is
 * wrong */
int gd_check_saved(const void *b, size_t size, const gd_model *m, const char *fn,
                   gd_dstate *out, int *mode, char *msg, size_t len);

#endif
