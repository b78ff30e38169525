//! An independent implementation of docs/model.md §4 exactly as the paper writes Eq. 14: SI units,
//! the coefficients A and B formed explicitly, `g` itself (not a deviation) as the state.
//! Deliberately shares nothing with the core but the parameter values.

/// Parameters in SI (the subset of docs/model.md §4 the law uses).
#[derive(Clone, Copy, Debug)]
pub struct RefParams {
    pub i0: f64,
    pub h0: f64,
    pub r0: f64,
    pub kp: f64,
    pub ki: f64,
    pub p0: f64,
    pub alpha: f64,
    pub n_sub: u32,
    pub parabolic: bool,
}

/// One row: g (A/m), current (A), force (N), voltage (V).
#[derive(Clone, Copy, Debug)]
pub struct RefRow {
    pub g: f64,
    pub current: f64,
    pub force: f64,
    pub voltage: f64,
}

/// Runs the law on gaps `h` sampled at step `dt`; row 0 is the initial state.
pub fn run(p: &RefParams, dt: f64, h: &[f64]) -> Vec<RefRow> {
    let k0 = p.p0 * p.h0 * p.h0 / (p.i0 * p.i0); // Eq. 7
    let g0 = p.i0 / p.h0;
    let big_g0 = 2.0 * k0; // Eq. 9
    let d = dt / p.n_sub as f64;
    let mut g = g0;
    let mut ea = p.r0 * p.i0 / p.ki; // KI·e_a(0) = R0·i0
    let row = |g: f64, ea: f64, h: f64| RefRow {
        g,
        current: g * h,
        force: k0 * g * g,
        voltage: p.kp * (g0 - g) + p.ki * ea, // Eq. 10
    };
    let mut rows = vec![row(g, ea, h[0])];
    let (mut h_prev, mut h_now) = (h[0], h[0]);
    for &h_next in &h[1..] {
        for k in 1..=p.n_sub {
            let s = k as f64 / p.n_sub as f64;
            let hk = if p.parabolic {
                // Parabola through (−1, h_prev), (0, h_now), (1, h_next).
                h_now + s * (h_next - h_prev) / 2.0 + s * s * (h_next - 2.0 * h_now + h_prev) / 2.0
            } else {
                h_now + s * (h_next - h_now)
            };
            let a = p.r0 * hk + p.kp + p.ki * d / 2.0;
            let b = p.ki * ea + p.ki * (g0 - g) * d / 2.0 + (p.kp + p.ki * d / 2.0) * g0;
            let g_new = (b + (big_g0 / d - (1.0 - p.alpha) * a) * g) / (big_g0 / d + a * p.alpha); // Eq. 14
            ea += ((g0 - g) + (g0 - g_new)) * d / 2.0; // Eq. 12
            g = g_new;
        }
        h_prev = h_now;
        h_now = h_next;
        rows.push(row(g, ea, h_next));
    }
    rows
}
