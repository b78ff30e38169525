//! An independent implementation of the Fig. 1 vehicle on a rigid rail (docs/model.md §2,
//! §4, §6, §9), written from the model page, never from `maglev_sim`: the equations of
//! motion by hand, the controllers in continuous time, classical RK4 at a small fixed step.
//!
//! Why this shape: `maglev run --set model=rigid` assembles the vehicle from Eq. 17/18
//! element matrices, integrates it with Newmark (γ = ½, β = ¼) inside a fixed-point loop on
//! the wheel forces, and runs each magnet through the paper's discrete Eq. 14 with n_sub
//! sub-steps. Here nothing of that is reused: the body is a Newton–Euler rigid body, the
//! massless wheel nodes are first-order force balances, the magnets are Eq. 9 + 10 as ODEs,
//! and one explicit RK4 advances all of it together (no iteration, no sub-steps, no matrices).
//! The two can only agree if both solve the same model; what remains is the run's time
//! discretisation error, which the tests measure and bound.
//!
//! # The model (deviations from static equilibrium, SI)
//!
//! Body DOFs (v, w, θx, θy, θz) about its CoM. Wheel i sits at r_i = (X_i, Y_i, −H) from the
//! CoM, H = 2 m the CoM height above the target lines (docs/model.md §9). The body end of the
//! wheel's spring–damper is the body point at r_i (rigid link): with small rotations it moves
//! by u + θ × r_i,
//!
//! ```text
//! y_a,i = v + X_i·θz + H·θx,       z_a,i = w + Y_i·θx − X_i·θy.
//! ```
//!
//! The wheel node has no mass, so its spring–damper carries exactly the magnet's force
//! change (docs/model.md §6: the vehicle load is G − p0 per magnet, and the guidance force):
//!
//! ```text
//! c·(ẏ_i − ẏ_a,i) + k·(y_i − y_a,i) = F_y,i,        F_y,i = G_L,i − G_R,i
//! c·(ż_i − ż_a,i) + k·(z_i − z_a,i) = G_z,i − p0
//! ```
//!
//! — a first-order ODE for each wheel DOF. The body receives the same forces at r_i
//! (Newton–Euler, small angles, moments r_i × F):
//!
//! ```text
//! m·v̈   = Σ F_y,i                 m·ẅ   = Σ (G_z,i − p0)
//! Jx·θ̈x = Σ (Y_i·(G_z,i − p0) + H·F_y,i)
//! Jy·θ̈y = Σ (−X_i·(G_z,i − p0))   Jz·θ̈z = Σ X_i·F_y,i
//! ```
//!
//! (Euler's gyroscopic terms are products of small rotation rates and drop out at this order,
//! as they do from the linear element matrices of Eq. 17 and 18.)
//!
//! Gaps on a rigid rail, geometry "paper" (docs/model.md §2), with the profile read at the
//! wheel's position x_i = x_i(0) + V·t:
//!
//! ```text
//! h_z = h0 + z_i + r_z(x_i),   d = y_i + r_y(x_i),   h_L = h0 + d,   h_R = h0 − d.
//! ```
//!
//! Each of the twelve magnets (one levitation, two guidance per wheel) is the continuous
//! controller the paper's Eq. 14 with its internal loop converges to (docs/model.md §4):
//!
//! ```text
//! G0·ġ = V − R0·h·g   (Eq. 9),   V = KP·e + KI·∫e   (Eq. 10),   e = g0 − g   (Eq. 8)
//! G = K0·g²   (Eq. 1),   K0 = p0·h0²/i0²   (Eq. 7),   G0 = 2·K0,   g0 = i0/h0
//! ```
//!
//! with the same p0 (a quarter of the weight) for the guidance magnets, and every controller
//! starting in equilibrium at its own initial gap: g = g0, KI·∫e = R0·h(0)·g0.

/// Fig. 1 vehicle and magnet data (SI), docs/model.md §4, §9.
#[derive(Clone, Copy, Debug)]
pub struct Params {
    pub body_mass: f64,
    pub jx: f64,
    pub jy: f64,
    pub jz: f64,
    pub k: f64,
    pub c: f64,
    /// Wheels at X = ±half_length from the CoM.
    pub half_length: f64,
    /// Wheels at Y = ±half_width from the vehicle centre.
    pub half_width: f64,
    /// CoM height above the target lines, H.
    pub body_height: f64,
    pub gravity: f64,
    pub i0: f64,
    pub h0: f64,
    pub r0: f64,
    pub kp: f64,
    pub ki: f64,
}

impl Params {
    /// The values of docs/model.md §9 (vehicle) and §4 (magnets), typed in from the page.
    pub fn paper() -> Self {
        Params {
            body_mass: 15_000.0,
            jx: 20.0e3,
            jy: 950.0e3,
            jz: 1600.0e3,
            k: 200.0e3,
            c: 10.0e3,
            half_length: 7.5,
            half_width: 1.5,
            body_height: 2.0,
            gravity: 9.81,
            i0: 43.0,
            h0: 0.01,
            r0: 1.0,
            kp: 0.01,
            ki: 6.0,
        }
    }

    /// Static load of each magnet: a quarter of the body's weight (docs/model.md §1).
    pub fn p0(&self) -> f64 {
        self.body_mass * self.gravity / 4.0
    }

    /// Wheel positions (X_i, Y_i) from the CoM, and their X at t = 0. Wheel 1 leads on the
    /// line nearest the beam axis (the vehicle centre is 1.5 m off it, so that line is at
    /// Y = −half_width from the centre) and is at x = 0 at t = 0 (docs/model.md §9).
    pub fn wheels(&self) -> [Wheel; 4] {
        let (a, b) = (self.half_length, self.half_width);
        let w = |x: f64, y: f64| Wheel {
            x,
            y,
            x_start: x - a,
        };
        [w(a, -b), w(a, b), w(-a, -b), w(-a, b)]
    }
}

/// Where a wheel is on the vehicle.
#[derive(Clone, Copy, Debug)]
pub struct Wheel {
    /// X from the CoM (m).
    pub x: f64,
    /// Y from the CoM (m).
    pub y: f64,
    /// Position along the track at t = 0 (m).
    pub x_start: f64,
}

/// How the profile is read between its points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interp {
    /// Straight lines between neighbouring points.
    Linear,
    /// The cubic through the two points on either side (4-point Lagrange).
    Cubic,
}

/// A rail irregularity profile `x → (r_y, r_z)` given at points, read between them by
/// [`Interp`] (clamped at the ends).
#[derive(Clone, Debug)]
pub struct Profile {
    x: Vec<f64>,
    ry: Vec<f64>,
    rz: Vec<f64>,
    interp: Interp,
}

impl Profile {
    /// From rows `[x, r_y, r_z]`: sorted by x, points closer than 1 nm to the previous one
    /// dropped (two wheels reaching the same x at different steps give the same value up to
    /// the rounding of x).
    pub fn new(mut rows: Vec<[f64; 3]>, interp: Interp) -> Self {
        rows.sort_by(|a, b| a[0].total_cmp(&b[0]));
        rows.dedup_by(|b, a| b[0] - a[0] < 1e-9);
        assert!(rows.len() >= 4, "a profile needs four points");
        Profile {
            x: rows.iter().map(|r| r[0]).collect(),
            ry: rows.iter().map(|r| r[1]).collect(),
            rz: rows.iter().map(|r| r[2]).collect(),
            interp,
        }
    }

    /// `(r_y, r_z)` at `x`.
    pub fn at(&self, x: f64) -> (f64, f64) {
        let n = self.x.len();
        let x = x.clamp(self.x[0], self.x[n - 1]);
        // The interval [x[j − 1], x[j]] holding x.
        let j = self.x.partition_point(|&xi| xi <= x).clamp(1, n - 1);
        match self.interp {
            Interp::Linear => {
                let s = (x - self.x[j - 1]) / (self.x[j] - self.x[j - 1]);
                let lerp = |v: &[f64]| v[j - 1] + s * (v[j] - v[j - 1]);
                (lerp(&self.ry), lerp(&self.rz))
            }
            Interp::Cubic => {
                let first = (j.max(2) - 2).min(n - 4);
                let xs = &self.x[first..first + 4];
                let mut w = [0.0; 4];
                for (a, wa) in w.iter_mut().enumerate() {
                    *wa = (0..4)
                        .filter(|&b| b != a)
                        .map(|b| (x - xs[b]) / (xs[a] - xs[b]))
                        .product();
                }
                let sum = |v: &[f64]| (0..4).map(|a| w[a] * v[first + a]).sum::<f64>();
                (sum(&self.ry), sum(&self.rz))
            }
        }
    }
}

/// One output row at a run's step time (SI).
#[derive(Clone, Copy, Debug, Default)]
pub struct Row {
    pub t: f64,
    pub wheel1_y: f64,
    pub wheel1_z: f64,
    pub wheel1_gap_z: f64,
    pub wheel1_force_z: f64,
    /// Every magnet's gap (m): per wheel (levitation h_z, guidance h_L, guidance h_R).
    pub gaps: [[f64; 3]; 4],
}

// State layout: body displacements (5), body velocities (5), wheel y (4), wheel z (4), then
// per wheel three magnets (levitation, guidance L, guidance R), each (g, ∫e).
const BODY: usize = 0;
const BODY_RATE: usize = 5;
const WHEEL_Y: usize = 10;
const WHEEL_Z: usize = 14;
const MAGNETS: usize = 18;
const N: usize = MAGNETS + 4 * 3 * 2;

/// The vehicle as an ODE ẋ = f(t, x).
struct System<'a> {
    p: Params,
    wheels: [Wheel; 4],
    profile: &'a Profile,
    speed: f64,
    p0: f64,
    k0: f64,
    g0: f64,
}

impl System<'_> {
    /// The three gaps (h_z, h_L, h_R) of wheel i at time t.
    fn gaps(&self, t: f64, x: &[f64; N], i: usize) -> [f64; 3] {
        let (ry, rz) = self.profile.at(self.wheels[i].x_start + self.speed * t);
        let h0 = self.p.h0;
        let d = x[WHEEL_Y + i] + ry;
        [h0 + x[WHEEL_Z + i] + rz, h0 + d, h0 - d]
    }

    /// Body-point displacement (or velocity, from the rates) at wheel i: (y_a, z_a).
    fn attach(&self, q: &[f64], i: usize) -> (f64, f64) {
        let (xw, yw, h) = (self.wheels[i].x, self.wheels[i].y, self.p.body_height);
        let (v, w, rx, ry, rz) = (q[0], q[1], q[2], q[3], q[4]);
        (v + xw * rz + h * rx, w + yw * rx - xw * ry)
    }

    fn deriv(&self, t: f64, x: &[f64; N]) -> [f64; N] {
        let p = &self.p;
        let mut dx = [0.0; N];
        // Body displacements → rates.
        dx[BODY..BODY + 5].copy_from_slice(&x[BODY_RATE..BODY_RATE + 5]);
        let (mut fy, mut fz, mut mx, mut my, mut mz) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..4 {
            let gaps = self.gaps(t, x, i);
            let mut force = [0.0; 3];
            for (m, &h) in gaps.iter().enumerate() {
                let s = MAGNETS + 6 * i + 2 * m;
                let (g, int_e) = (x[s], x[s + 1]);
                let e = self.g0 - g; // Eq. 8
                let volt = p.kp * e + p.ki * int_e; // Eq. 10
                dx[s] = (volt - p.r0 * h * g) / (2.0 * self.k0); // Eq. 9, G0 = 2 K0
                dx[s + 1] = e;
                force[m] = self.k0 * g * g; // Eq. 1
            }
            let f_z = force[0] - self.p0;
            let f_y = force[1] - force[2]; // geometry "paper": G_L − G_R
                                           // Massless wheel: c·(u̇ − u̇_a) + k·(u − u_a) = F.
            let (ya, za) = self.attach(&x[BODY..BODY + 5], i);
            let (ya_dot, za_dot) = self.attach(&x[BODY_RATE..BODY_RATE + 5], i);
            dx[WHEEL_Y + i] = ya_dot + (f_y - p.k * (x[WHEEL_Y + i] - ya)) / p.c;
            dx[WHEEL_Z + i] = za_dot + (f_z - p.k * (x[WHEEL_Z + i] - za)) / p.c;
            // The spring–damper passes F on to the body point r_i = (X_i, Y_i, −H).
            let (xw, yw, h) = (self.wheels[i].x, self.wheels[i].y, p.body_height);
            fy += f_y;
            fz += f_z;
            mx += yw * f_z + h * f_y; // (r × F)_x = Y·F_z − (−H)·F_y
            my += -xw * f_z; // (r × F)_y = (−H)·F_x − X·F_z, F_x = 0
            mz += xw * f_y; // (r × F)_z = X·F_y − Y·F_x
        }
        dx[BODY_RATE] = fy / p.body_mass;
        dx[BODY_RATE + 1] = fz / p.body_mass;
        dx[BODY_RATE + 2] = mx / p.jx;
        dx[BODY_RATE + 3] = my / p.jy;
        dx[BODY_RATE + 4] = mz / p.jz;
        dx
    }

    fn row(&self, t: f64, x: &[f64; N]) -> Row {
        let gaps = [0, 1, 2, 3].map(|i| self.gaps(t, x, i));
        let g = x[MAGNETS];
        Row {
            t,
            wheel1_y: x[WHEEL_Y],
            wheel1_z: x[WHEEL_Z],
            wheel1_gap_z: gaps[0][0],
            wheel1_force_z: self.k0 * g * g,
            gaps,
        }
    }
}

/// Runs the vehicle at `speed` over `profile` from rest at its static position, reporting at
/// t_n = n·dt_out for n = 0..=steps; RK4 with `substeps` steps per output interval (the
/// profile's kinks, at the run's step times, then fall on RK4 step boundaries).
pub fn simulate(
    p: &Params,
    profile: &Profile,
    speed: f64,
    dt_out: f64,
    steps: usize,
    substeps: usize,
) -> Vec<Row> {
    let p0 = p.p0();
    let sys = System {
        p: *p,
        wheels: p.wheels(),
        profile,
        speed,
        p0,
        k0: p0 * p.h0 * p.h0 / (p.i0 * p.i0), // Eq. 7
        g0: p.i0 / p.h0,
    };
    let mut x = [0.0; N];
    for i in 0..4 {
        for (m, h) in sys.gaps(0.0, &x, i).into_iter().enumerate() {
            let s = MAGNETS + 6 * i + 2 * m;
            x[s] = sys.g0;
            x[s + 1] = p.r0 * h * sys.g0 / p.ki; // KI·∫e(0) = R0·h(0)·g0
        }
    }
    let h = dt_out / substeps as f64;
    let mut rows = Vec::with_capacity(steps + 1);
    rows.push(sys.row(0.0, &x));
    for n in 0..steps {
        let t_n = n as f64 * dt_out;
        for s in 0..substeps {
            let t = t_n + s as f64 * h;
            x = rk4_step(&sys, t, &x, h);
        }
        rows.push(sys.row((n + 1) as f64 * dt_out, &x));
    }
    rows
}

/// One classical fourth-order Runge–Kutta step.
fn rk4_step(sys: &System, t: f64, x: &[f64; N], h: f64) -> [f64; N] {
    let add = |a: &[f64; N], b: &[f64; N], s: f64| -> [f64; N] {
        let mut r = *a;
        for (r, b) in r.iter_mut().zip(b) {
            *r += s * b;
        }
        r
    };
    let k1 = sys.deriv(t, x);
    let k2 = sys.deriv(t + h / 2.0, &add(x, &k1, h / 2.0));
    let k3 = sys.deriv(t + h / 2.0, &add(x, &k2, h / 2.0));
    let k4 = sys.deriv(t + h, &add(x, &k3, h));
    let mut r = *x;
    for j in 0..N {
        r[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn smooth() -> Profile {
        let rows = (0..4)
            .map(|k| [-100.0 + 400.0 * k as f64, 0.0, 0.0])
            .collect();
        Profile::new(rows, Interp::Linear)
    }

    #[test]
    fn smooth_rail_stays_in_equilibrium() {
        let rows = simulate(&Params::paper(), &smooth(), 100.0, 1e-3, 100, 10);
        let p0 = Params::paper().p0();
        for r in &rows {
            assert!(r.wheel1_z.abs() < 1e-15 && r.wheel1_y.abs() < 1e-15);
            assert!((r.wheel1_force_z - p0).abs() < 1e-9 * p0);
        }
    }

    #[test]
    fn a_step_in_the_rail_moves_the_wheel_with_it_and_restores_the_force() {
        // The rail drops by 1 mm everywhere ahead of x = 1 m: the gap opens, the force falls,
        // the PI integral restores g = g0 (force p0) at any gap (docs/model.md §2 item 1),
        // the vehicle sinks toward the rail and the gap partly closes again.
        let prof = Profile::new(
            vec![
                [-100.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.001, 0.0, 1e-3],
                [1000.0, 0.0, 1e-3],
            ],
            Interp::Linear,
        );
        let p = Params::paper();
        let rows = simulate(&p, &prof, 10.0, 1e-3, 3000, 10);
        let last = rows.last().unwrap();
        assert!((last.wheel1_force_z - p.p0()).abs() < 1e-3 * p.p0());
        assert!(last.wheel1_z < 0.0, "the wheel sank: {}", last.wheel1_z);
        let min_force = rows
            .iter()
            .map(|r| r.wheel1_force_z)
            .fold(f64::MAX, f64::min);
        // Linearised (docs/model.md §2 item 1), a held wheel's magnet answers the step
        // η = 0.1 with x(s) = −s·η/(τs² + 2s + ki): a force dip of 2·η/(τ·ω_d) ≈ 1.3 % at
        // ω_d = 38.75 rad/s. The wheel yields to it, so the dip is smaller, but not tiny.
        assert!(
            min_force < 0.995 * p.p0(),
            "the force dropped at the step: {min_force} N"
        );
    }

    #[test]
    fn profile_interpolates_and_clamps() {
        // Points of r_z = x³ − x (and r_y = 2x) at x = 0, 0.5, 1, 1.5, 2, one given twice.
        let f = |x: f64| [x, 2.0 * x, x * x * x - x];
        let pts: Vec<[f64; 3]> = [1.0, 0.0, 2.0, 0.5, 1.5, 1.0 + 1e-12].map(f).to_vec();
        let lin = Profile::new(pts.clone(), Interp::Linear);
        let cub = Profile::new(pts, Interp::Cubic);
        assert_eq!(lin.at(0.25), (0.5, 0.5 * (f(0.0)[2] + f(0.5)[2])));
        // A cubic comes back exactly, in every interval, the end ones included.
        for x in [0.1, 0.7, 1.2, 1.9] {
            let (ry, rz) = cub.at(x);
            assert!(
                (ry - 2.0 * x).abs() < 1e-14 && (rz - f(x)[2]).abs() < 1e-14,
                "{x}"
            );
        }
        assert_eq!(lin.at(-1.0), (0.0, 0.0));
        assert_eq!(cub.at(5.0), (4.0, 6.0));
    }
}
