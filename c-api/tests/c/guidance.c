/* Host C test program (tests/host_c.rs): a guidance pair through the C API's guidance law
 * (maglev_guidance_*_f32), one line of output bits per step; the Rust test runs the same
 * trace through maglev_core's GuidanceLaw and requires the same lines. Then the refusals. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "maglev.h"

#define STEPS 200

static double offset(int k) { return 0.01 + 0.004 * (double)((k * 37) % 41 - 20) / 20.0; }
static double accel_y(int k) { return 0.01 * (double)((k * 13) % 17 - 8); }

static uint32_t bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static void params(maglev_params *p, maglev_guidance_params *g) {
    maglev_params_paper(10000.0, 1e-4, p);
    p->law = MAGLEV_LAW_STATE;
    p->state = (maglev_state_params){51600.0, 1600.0, 40.0, 4300.0, 10.0, 500.0,
                                     10000.0, 300.0, MAGLEV_GEOMETRY_EMS};
    *g = (maglev_guidance_params){20000.0, 900.0, 25.0, 3000.0, 8.0};
}

int main(void) {
    maglev_params p;
    maglev_guidance_params g;
    params(&p, &g);
    static maglev_guidance_law_f32 law;
    maglev_guidance_state_f32 st;
    int32_t rc = maglev_guidance_init_f32(&p, &g, &law);
    if (rc == MAGLEV_OK) rc = maglev_guidance_state_init_f32(&law, 1e-4, &st);
    printf("guidance init %d\n", rc);
    for (int k = 1; rc == MAGLEV_OK && k <= STEPS; k++) {
        maglev_pair_measurement_f32 m = {(float)offset(k), (float)accel_y(k),
                                         k % 3 ? MAGLEV_MEASURED_ACCEL : 0u};
        maglev_pair_output_f32 o;
        int32_t r = maglev_guidance_update_f32(&law, &st, &m, &o);
        printf("guidance %03d rc=%d vl=%08x vr=%08x Fl=%08x Fr=%08x Fy=%08x st=%02x\n", k, r,
               bits(o.left.voltage_pu), bits(o.right.voltage_pu), bits(o.left.force_pu),
               bits(o.right.force_pu), bits(o.force_y_pu), o.status);
    }
    /* Refusals: a negative gain names its field; the paper's law has no timing to share. */
    params(&p, &g);
    g.kd_V_s_per_m = -1.0;
    rc = maglev_guidance_init_f32(&p, &g, &law);
    printf("bad kd %d %s\n", rc, maglev_error_field_name(rc));
    params(&p, &g);
    p.law = MAGLEV_LAW_PAPER;
    rc = maglev_guidance_init_f32(&p, &g, &law);
    printf("paper law %d %s\n", rc, maglev_error_field_name(rc));
    printf("uninitialised %d\n", maglev_guidance_state_init_f32(&law, 0.0, &st));
    return 0;
}
