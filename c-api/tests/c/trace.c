/* Host C test program (tests/host_c.rs): one gap trace through the C API, every law in both
 * variants, one line of output bits per step. The Rust test runs the same trace through
 * maglev_core::Law and requires the same lines. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "maglev.h"

#define STEPS 200

static double gap(int k) {
    if (k == 150) return 0.0; /* collision */
    if (k == 170) return 100.0;             /* beyond every law's range (and Q4.28's) */
    if (k == 180) return __builtin_nan(""); /* refused, state held */
    return 1.0 + 0.002 * (double)((k * 37) % 41 - 20);
}
static double accel(int k) { return 0.01 * (double)((k * 13) % 17 - 8); }

static uint32_t bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

#define LAWS 4
static const char *const names[LAWS] = {"paper", "gap-loop", "state", "state-small"};

/* The README's state gains (kp per unit 12: beyond Q4.28's range, refused), and smaller
 * ones with a 40 Hz observer that Q4.28 can carry (its gain ω²·δ must stay below 8). */
static void params_of(int i, maglev_params *p) {
    maglev_params_paper(15000.0 * 9.81 / 4.0, 1e-3, p);
    const uint32_t kinds[LAWS] = {MAGLEV_LAW_PAPER, MAGLEV_LAW_GAP_LOOP, MAGLEV_LAW_STATE,
                                  MAGLEV_LAW_STATE};
    p->law = kinds[i];
    if (i == 2) {
        p->state = (maglev_state_params){51600.0, 1600.0, 40.0, 4300.0, 10.0, 500.0,
                                         10000.0, 300.0, MAGLEV_GEOMETRY_EMS};
    } else if (i == 3) {
        p->state = (maglev_state_params){20000.0, 1000.0, 20.0, 3000.0, 5.0, 300.0,
                                         10000.0, 40.0, MAGLEV_GEOMETRY_EMS};
    }
}

static void run_f32(int law_kind) {
    maglev_params p;
    params_of(law_kind, &p);
    static maglev_law_f32 law;
    maglev_state_f32 st;
    int32_t rc = maglev_law_init_f32(&p, &law);
    if (rc == MAGLEV_OK) rc = maglev_state_init_f32(&law, p.h0_m, &st);
    printf("%s f32 init %d\n", names[law_kind], rc);
    for (int k = 1; rc == MAGLEV_OK && k <= STEPS; k++) {
        maglev_measurement_f32 m = {(float)gap(k), (float)accel(k), 0.0f, MAGLEV_MEASURED_ACCEL};
        maglev_output_f32 o;
        int32_t r = maglev_law_update_f32(&law, &st, &m, &o);
        printf("%s f32 %03d rc=%d g=%08x F=%08x i=%08x v=%08x st=%02x\n", names[law_kind], k, r,
               bits(o.g_pu), bits(o.force_pu), bits(o.current_pu), bits(o.voltage_pu),
               o.status);
    }
}

static void run_q28(int law_kind) {
    maglev_params p;
    params_of(law_kind, &p);
    static maglev_law_q28 law;
    maglev_state_q28 st;
    int32_t rc = maglev_law_init_q28(&p, &law);
    if (rc == MAGLEV_OK) rc = maglev_state_init_q28(&law, p.h0_m, &st);
    printf("%s q28 init %d\n", names[law_kind], rc);
    for (int k = 1; rc == MAGLEV_OK && k <= STEPS; k++) {
        maglev_measurement_q28 m = {0, 0, 0, MAGLEV_MEASURED_ACCEL};
        maglev_q28_from_f64(gap(k), &m.gap_pu);
        maglev_q28_from_f64(accel(k), &m.accel_g);
        maglev_output_q28 o;
        int32_t r = maglev_law_update_q28(&law, &st, &m, &o);
        printf("%s q28 %03d rc=%d g=%08x F=%08x i=%08x v=%08x st=%02x\n", names[law_kind], k, r,
               (uint32_t)o.g_pu, (uint32_t)o.force_pu, (uint32_t)o.current_pu,
               (uint32_t)o.voltage_pu, o.status);
    }
}

int main(void) {
    for (int law = 0; law < LAWS; law++) {
        run_f32(law);
        run_q28(law);
    }
    return 0;
}
