#include <stdio.h>
#include "maglev.h"

int main(void) {
    maglev_params p;
    maglev_params_paper(36787.5, 1e-3, &p);  /* a quarter of a 15 t body (N), 1 kHz */
    p.law = MAGLEV_LAW_GAP_LOOP;             /* p.gap_loop holds the designed gains */
    static maglev_law_f32 law;               /* MAGLEV_LAW_SIZE bytes, caller-owned */
    maglev_state_f32 st;
    int32_t rc = maglev_law_init_f32(&p, &law);
    if (rc == MAGLEV_OK) rc = maglev_state_init_f32(&law, p.h0_m, &st);
    if (rc != MAGLEV_OK) { fprintf(stderr, "maglev: %s\n", maglev_error_message(rc)); return 2; }
    for (int k = 1; k <= 5; k++) {
        maglev_measurement_f32 m = {.gap_pu = 1.0f + 0.01f * (float)k};  /* h/h0 */
        maglev_output_f32 out;
        maglev_law_update_f32(&law, &st, &m, &out);
        printf("%d %.3f N %.4f A\n", k, out.force_pu * p.p0_N, out.current_pu * p.i0_A);
    }
    return 0;
}
