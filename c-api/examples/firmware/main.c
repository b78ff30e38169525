/* C firmware example for the mps2-an386 Cortex-M4F (QEMU): the Rust `qemu-m4` image's
 * self-test trace (firmware-sim/src/board/selftest.rs) through the C API, the same lines bit
 * for bit, then the instructions of one update counted as the Rust image counts them
 * (firmware-sim/src/board/icount.rs: QEMU -icount shift=10, SysTick read around one call).
 * Built and run by scripts/c-firmware.sh; docs/c-api.md. */
#include <stdint.h>
#include <string.h>

#include "board.h"
#include "maglev.h"

/* ---- output ---------------------------------------------------------------------------- */

static char line[160];
static uint32_t pos;

static void put_str(const char *s) {
    while (*s && pos < sizeof line) line[pos++] = *s++;
}
static void put_hex(uint32_t v, int digits) {
    for (int i = digits - 1; i >= 0; i--) {
        if (pos < sizeof line) line[pos++] = "0123456789abcdef"[(v >> (4 * i)) & 0xf];
    }
}
static void put_dec(uint32_t v, int min_digits) {
    char d[10];
    int n = 0;
    do {
        d[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v || n < min_digits);
    while (n && pos < sizeof line) line[pos++] = d[--n];
}
static void flush_line(void) {
    put_str("\n");
    board_write(line, pos);
    pos = 0;
}
static uint32_t bits_f32(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* ---- instruction counting (the Rust image's method) ---------------------------------- */

#define SYST_CSR (*(volatile uint32_t *)0xE000E010)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018)
#define SYST_MASK 0x00FFFFFFu

typedef void (*call_t)(void *);

/* Every measurement goes through this one window: read SysTick, call, read SysTick. */
__attribute__((noinline)) static uint32_t ticks(call_t f, void *ctx) {
    uint32_t t0 = SYST_CVR;
    f(ctx);
    uint32_t t1 = SYST_CVR;
    return (t0 - t1) & SYST_MASK;
}

__attribute__((noinline)) static void nothing(void *ctx) { (void)ctx; }
__attribute__((noinline)) static void nops_100(void *ctx) {
    (void)ctx;
    __asm__ volatile(".rept 100\n\tnop\n\t.endr");
}
__attribute__((noinline)) static void nops_500(void *ctx) {
    (void)ctx;
    __asm__ volatile(".rept 500\n\tnop\n\t.endr");
}
__attribute__((noinline)) static void nops_1000(void *ctx) {
    (void)ctx;
    __asm__ volatile(".rept 1000\n\tnop\n\t.endr");
}

static uint32_t empty_ticks, ticks_per_900;

/* Instructions of `f(ctx)` beyond an empty call; 0 without a usable calibration. */
static uint32_t count(call_t f, void *ctx) {
    uint32_t t = ticks(f, ctx);
    if (ticks_per_900 == 0) return 0;
    uint32_t d = t > empty_ticks ? t - empty_ticks : 0;
    return (uint32_t)(((uint64_t)d * 900 + ticks_per_900 / 2) / ticks_per_900);
}

static uint32_t calibrate(void) {
    SYST_CSR = 0;
    SYST_RVR = SYST_MASK;
    SYST_CVR = 0;
    SYST_CSR = 5; /* core clock, enabled, no interrupt */
    empty_ticks = ticks(nothing, 0);
    uint32_t t100 = ticks(nops_100, 0);
    uint32_t t1000 = ticks(nops_1000, 0);
    ticks_per_900 = t1000 > t100 ? t1000 - t100 : 0;
    return count(nops_500, 0) - count(nops_100, 0);
}

/* ---- the self-test trace (selftest.rs: DT, STEPS, gap, Config) ----------------------- */

#define STEPS 32
#define DT_S 1e-3

static double trace_gap(int k) {
    if (k >= 4 && k <= 11) return 1.0 + 0.01 * (double)(k - 3);
    if (k >= 12 && k <= 15) return 1.08;
    if (k >= 16 && k <= 23) return 0.92 + 0.01 * (double)(k - 16);
    if (k == 27) return 0.0;
    if (k == 29) return 250.0;
    return 1.0;
}

struct config {
    const char *tag;
    uint32_t n_sub, interpolation;
    double v_max_V;
};
static const struct config configs[2] = {
    {"n1", 1, MAGLEV_INTERPOLATION_LINEAR, __builtin_inf()},
    {"n10p60v", 10, MAGLEV_INTERPOLATION_PARABOLIC, 60.0},
};

static int params_of(const struct config *c, maglev_params *p) {
    /* The paper's wheel magnet: a quarter of the 15 t body (Params::paper_wheel). */
    if (maglev_params_paper(15000.0 * 9.81 / 4.0, DT_S, p) != MAGLEV_OK) return 0;
    p->n_sub = c->n_sub;
    p->interpolation = c->interpolation;
    p->v_max_V = c->v_max_V;
    return 1;
}

struct counts {
    uint32_t nominal_min, nominal_max, max, measured;
};
static void add_count(struct counts *c, uint32_t n, uint32_t status) {
    c->measured = 1;
    if (status == 0) {
        if (n < c->nominal_min) c->nominal_min = n;
        if (n > c->nominal_max) c->nominal_max = n;
    }
    if (n > c->max) c->max = n;
}

static void put_head(const char *scalar, const char *tag, int k, uint32_t h) {
    put_str(scalar);
    put_str("/");
    put_str(tag);
    put_str(" ");
    put_dec((uint32_t)k, 2);
    put_str(" h=");
    put_hex(h, 8);
}
static void put_tail(uint32_t x, uint32_t y, uint32_t v, uint32_t F, uint32_t i, uint32_t st) {
    put_str(" x=");
    put_hex(x, 8);
    put_str(" y=");
    put_hex(y, 8);
    put_str(" v=");
    put_hex(v, 8);
    put_str(" F=");
    put_hex(F, 8);
    put_str(" i=");
    put_hex(i, 8);
    put_str(" st=");
    put_hex(st, 2);
    flush_line();
}

static maglev_law_f32 law_f32;
static maglev_state_f32 state_f32;
static maglev_law_q28 law_q28;
static maglev_state_q28 state_q28;

struct update_f32 {
    const maglev_law_f32 *law;
    maglev_state_f32 *state;
    maglev_measurement_f32 m;
    maglev_output_f32 out;
    int32_t rc;
};
static void call_update_f32(void *p) {
    struct update_f32 *u = p;
    u->rc = maglev_law_update_f32(u->law, u->state, &u->m, &u->out);
}

struct update_q28 {
    const maglev_law_q28 *law;
    maglev_state_q28 *state;
    maglev_measurement_q28 m;
    maglev_output_q28 out;
    int32_t rc;
};
static void call_update_q28(void *p) {
    struct update_q28 *u = p;
    u->rc = maglev_law_update_q28(u->law, u->state, &u->m, &u->out);
}

/* A function of maglev_law_update_f32's signature that returns at once, called in the same
 * window: the harness's share of a count (as the Rust image's `update_shaped`). */
__attribute__((noinline)) int32_t shaped_f32(const maglev_law_f32 *law, maglev_state_f32 *state,
                                             const maglev_measurement_f32 *m,
                                             maglev_output_f32 *out) {
    (void)law, (void)state, (void)m, (void)out;
    return 0;
}
static void call_shaped_f32(void *p) {
    struct update_f32 *u = p;
    u->rc = shaped_f32(u->law, u->state, &u->m, &u->out);
}

static int report_error(const char *what, int32_t rc) {
    put_str(what);
    put_str(": ");
    put_str(maglev_error_message(rc));
    flush_line();
    return 0;
}

static int run_f32(const struct config *c, struct counts *n) {
    maglev_params p;
    if (!params_of(c, &p)) return 0;
    int32_t rc = maglev_law_init_f32(&p, &law_f32);
    if (rc != MAGLEV_OK) return report_error("f32 init", rc);
    rc = maglev_state_init_f32(&law_f32, p.h0_m, &state_f32);
    if (rc != MAGLEV_OK) return report_error("f32 state", rc);
    struct update_f32 u = {.law = &law_f32, .state = &state_f32};
    for (int k = 1; k <= STEPS; k++) {
        u.m.gap_pu = (float)trace_gap(k);
        uint32_t insns = count(call_update_f32, &u);
        if (u.rc != MAGLEV_OK) return report_error("f32 update", u.rc);
        add_count(n, insns, u.out.status);
        maglev_state_view_f32 s;
        maglev_state_read_f32(&state_f32, &s);
        put_head("f32", c->tag, k, bits_f32(u.m.gap_pu));
        put_tail(bits_f32(s.x), bits_f32(s.y), bits_f32(s.v), bits_f32(u.out.force_pu),
                 bits_f32(u.out.current_pu), u.out.status);
    }
    return 1;
}

static int run_q28(const struct config *c, struct counts *n) {
    maglev_params p;
    if (!params_of(c, &p)) return 0;
    int32_t rc = maglev_law_init_q28(&p, &law_q28);
    if (rc != MAGLEV_OK) return report_error("q28 init", rc);
    rc = maglev_state_init_q28(&law_q28, p.h0_m, &state_q28);
    if (rc != MAGLEV_OK) return report_error("q28 state", rc);
    struct update_q28 u = {.law = &law_q28, .state = &state_q28};
    for (int k = 1; k <= STEPS; k++) {
        /* 0x80: the gap saturated on conversion (250 h0 is beyond Q4.28's range). */
        uint32_t saturated = maglev_q28_from_f64(trace_gap(k), &u.m.gap_pu) == MAGLEV_ERROR_RANGE;
        uint32_t insns = count(call_update_q28, &u);
        if (u.rc != MAGLEV_OK) return report_error("q28 update", u.rc);
        add_count(n, insns, u.out.status);
        maglev_state_view_q28 s;
        maglev_state_read_q28(&state_q28, &s);
        put_head("i4f28", c->tag, k, (uint32_t)u.m.gap_pu);
        put_tail((uint32_t)s.x, (uint32_t)s.y, (uint32_t)s.v, (uint32_t)u.out.force_pu,
                 (uint32_t)u.out.current_pu, u.out.status | (saturated ? 0x80 : 0));
    }
    return 1;
}

static void report(const char *scalar, const char *tag, const struct counts *n) {
    put_str("insns c-api ");
    put_str(scalar);
    put_str("/");
    put_str(tag);
    if (!n->measured || ticks_per_900 == 0) {
        put_str(" update: not measured");
    } else {
        put_str(" update: nominal ");
        put_dec(n->nominal_min, 1);
        put_str("..");
        put_dec(n->nominal_max, 1);
        put_str(", max ");
        put_dec(n->max, 1);
    }
    flush_line();
}

int main(void) {
    put_str("maglev C API self-test: mps2-an386, cortex-m4, f32 + q4.28 (i4f28)");
    flush_line();
    uint32_t check = calibrate();
    put_str("icount: ");
    put_dec(ticks_per_900, 1);
    put_str(" SysTick ticks per 900 instructions; 500 nops - 100 nops = ");
    put_dec(check, 1);
    put_str(" (want 400)");
    flush_line();

    struct counts n[4];
    for (int i = 0; i < 4; i++) n[i] = (struct counts){UINT32_MAX, 0, 0, 0};
    int ok = 1;
    for (int i = 0; i < 2; i++) {
        ok = ok && run_f32(&configs[i], &n[2 * i]);
        ok = ok && run_q28(&configs[i], &n[2 * i + 1]);
    }
    for (int i = 0; ok && i < 2; i++) {
        report("f32", configs[i].tag, &n[2 * i]);
        report("i4f28", configs[i].tag, &n[2 * i + 1]);
    }
    struct update_f32 u = {.law = &law_f32, .state = &state_f32};
    put_str("insns c-api f32 update-shaped call that returns at once (the harness): ");
    put_dec(count(call_shaped_f32, &u), 1);
    flush_line();
    return ok && check == 400 ? 0 : 1;
}
