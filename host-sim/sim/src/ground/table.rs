//! W(x) of [`super::green`] tabulated once per soil on a grid chosen from the error it
//! leaves, and the cache of such tables a caller keeps across runs ([`Tables`]).
//!
//! # The bound
//!
//! |W_table(x) − W(x)| ≤ [`BOUND`] for every x ≥ 0, W(x) the direct evaluation (the
//! real-axis quadrature [`Green::scaled`]; W(0) = 1 − ν ≈ 0.5–1, so the bound is about 1e-5 of
//! the static value). It is spent in three parts of at most BOUND/4 each:
//!
//! 1. **Interpolation.** f(x) = W(x)·e^{i·Re(q_R)·x} (the Rayleigh wave's phase taken out, so
//!    f varies on the scale of the body waves' beat with it) is read by cubic Lagrange
//!    interpolation on four neighbouring nodes. Its error on an interval of width h is at most
//!    max|∏(t − t_j)|·h⁴/4!·max|f⁽⁴⁾| with max|∏(t − t_j)| = 9/16 on the middle interval and
//!    15/16 on the first interval of the table (read with t ∈ [−1, 0]); with the fourth
//!    difference Δ⁴f = h⁴f⁽⁴⁾(ζ) this is estimated, per component, as
//!    (15/16)/24·(|Re Δ⁴f| + |Im Δ⁴f|), the largest over the block. The x axis is cut into
//!    blocks of [`BLOCK`]; each block's spacing starts at 0.5 and is halved until that
//!    estimate is below BOUND/4 (to at most 2⁻⁹·BLOCK; a block that cannot reach it is an
//!    error).
//! 2. **The far form.** From x = [`Far::from_x`] (40 for ν ≤ 0.38) the nodes are the
//!    contour-deformed form of far.rs (exact up to Hankel's series and its quadrature);
//!    host-sim/sim/tests/ground_table.rs holds it within BOUND/4 of the direct evaluation at
//!    the switch-over and beyond.
//! 3. **The cut-off.** W is taken as 0 from the start of the first block beyond the
//!    Rayleigh wave's envelope maximum (√x·e^{x·Im q_R} peaks at x = 1/(2|Im q_R|)) and
//!    beyond the far form's start whose nodes are all below BOUND/4: beyond it each part of
//!    (G4) decays exponentially (e^{x·Im q_b}, Im q_b < 0).
//!
//! The test host-sim/sim/tests/ground_table.rs checks the whole bound against the direct
//! evaluation at points between the nodes. What it means for a level: a receiver's spectrum
//! is Σ_k W(x_k)·S_k/r_k over the piers, so its error is at most
//! BOUND·Σ_k|S_k|/r_k / |Σ_k W(x_k)·S_k/r_k| of it, relative; the paper-5 levels move by at
//! most a few thousandths of a dB (docs/ground.md, "Cost").
//!
//! # Reuse
//!
//! A node's value depends only on ν, ξ and the node's x, and a block's spacing only on its
//! own nodes, so a table extended block by block holds the same bits as one built at once:
//! [`Tables`] keys its tables by (ν, ξ) (the grid follows from them and [`BOUND`]) and extends
//! a table when a later run needs a larger x. It is a value the caller owns and passes in (no
//! global state): `maglev report` keeps one for its two runs (docs/ground.md).

use super::far::Far;
use super::green::Green;
use crate::{Error, Result};
use rustfft::num_complex::Complex64 as C;

/// The table's bound on |W_table − W| (module docs).
pub const BOUND: f64 = 1e-5;
/// The width in x of a block of one spacing.
pub const BLOCK: f64 = 8.0;
/// A block's first spacing is BLOCK/2^COARSEST (0.5), its finest BLOCK/2^FINEST.
const COARSEST: u32 = 4;
const FINEST: u32 = 9;
/// The interpolation error per unit fourth difference (module docs, part 1).
const PER_DIFFERENCE: f64 = 15.0 / 16.0 / 24.0;

/// One block: nodes from `first` at spacing 1/`inv_h`, f = W·e^{i·Re(q_R)·x} at each.
#[derive(Clone, Debug)]
struct Block {
    first: f64,
    inv_h: f64,
    values: Vec<C>,
}

/// W(x) of one soil tabulated to its bound (module docs).
#[derive(Clone, Debug)]
pub struct Table {
    green: Green,
    far: Far,
    xi: f64,
    /// Re q_R: the phase taken out of the nodes.
    phase: f64,
    /// The Rayleigh envelope's maximum, 1/(2|Im q_R|).
    envelope_peak: f64,
    blocks: Vec<Block>,
    /// W = 0 from here on, once found.
    end: Option<f64>,
}

impl Table {
    /// An empty table for Poisson's ratio `nu` and damping ratio `xi` (the ranges of
    /// [`Green::new`]).
    pub fn new(nu: f64, xi: f64) -> Result<Self> {
        let green = Green::new(nu, xi)?;
        let far = Far::new(&green)?;
        let q_r = green.rayleigh_pole()?;
        Ok(Table {
            green,
            far,
            xi,
            phase: q_r.re,
            envelope_peak: 0.5 / -q_r.im,
            blocks: Vec::new(),
            end: None,
        })
    }

    /// The Green's function tabulated.
    pub fn green(&self) -> &Green {
        &self.green
    }

    /// The x up to which [`Table::at`] may be read (infinite once the cut-off is found).
    pub fn covered(&self) -> f64 {
        if self.end.is_some() {
            f64::INFINITY
        } else {
            self.blocks.len() as f64 * BLOCK
        }
    }

    /// Extend the table until it covers `x_max` (or its cut-off).
    pub fn cover(&mut self, x_max: f64) -> Result<()> {
        while self.blocks.is_empty() || self.covered() < x_max {
            let k = self.blocks.len();
            let block = self.block(k)?;
            let x0 = k as f64 * BLOCK;
            let small = block.values.iter().all(|v| v.norm() <= BOUND / 4.0);
            if small && x0 >= self.far.from_x() && x0 >= self.envelope_peak {
                self.end = Some(x0);
            } else {
                self.blocks.push(block);
            }
        }
        Ok(())
    }

    /// f = W·e^{i·Re(q_R)·x} at one node: the direct evaluation below the far form's start.
    fn node(&self, x: f64) -> C {
        let w = if x < self.far.from_x() {
            self.green.scaled(x)
        } else {
            self.far.scaled(x)
        };
        w * C::from_polar(1.0, self.phase * x)
    }

    /// Block `k`, its spacing halved until its interpolation estimate meets BOUND/4.
    fn block(&self, k: usize) -> Result<Block> {
        let x0 = k as f64 * BLOCK;
        for level in COARSEST..=FINEST {
            let n = 1_usize << level;
            let h = BLOCK / n as f64;
            let first = if k == 0 { 0.0 } else { x0 - h };
            let values: Vec<C> = (0..n + 3)
                .map(|j| self.node(first + j as f64 * h))
                .collect();
            if PER_DIFFERENCE * largest_fourth_difference(&values) <= BOUND / 4.0 {
                return Ok(Block {
                    first,
                    inv_h: 1.0 / h,
                    values,
                });
            }
        }
        Err(Error::numerical(format!(
            "ground: the table of W cannot meet its bound {BOUND:e} at x = {x0} with a spacing \
             of {} (poisson = {}, damping = {})",
            BLOCK / (1 << FINEST) as f64,
            self.green.poisson(),
            self.xi
        )))
    }

    /// The spacing of the block holding `x` (for the docs' figures and the tests).
    pub fn spacing_at(&self, x: f64) -> Option<f64> {
        self.blocks.get((x / BLOCK) as usize).map(|b| 1.0 / b.inv_h)
    }

    /// The cut-off, once found: W = 0 from there on.
    pub fn end(&self) -> Option<f64> {
        self.end
    }

    /// The number of nodes (for the docs' figures and the tests).
    pub fn nodes(&self) -> usize {
        self.blocks.iter().map(|b| b.values.len()).sum()
    }

    /// e^{i·Re(q_R)·x}·W(x) by cubic Lagrange interpolation, for 0 ≤ x ≤ [`Table::covered`]
    /// (0 beyond the cut-off): multiply by e^{−i·Re(q_R)·x} ([`Table::phase`]) for W.
    pub fn shifted(&self, x: f64) -> C {
        if self.end.is_some_and(|e| x >= e) {
            return C::new(0.0, 0.0);
        }
        let k = ((x / BLOCK) as usize).min(self.blocks.len() - 1);
        let b = &self.blocks[k];
        let u = (x - b.first) * b.inv_h;
        let i = (u.floor() as usize).clamp(1, b.values.len() - 3);
        let t = u - i as f64;
        let v = &b.values[i - 1..i + 3];
        let w = [
            -t * (t - 1.0) * (t - 2.0) / 6.0,
            (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0,
            -(t + 1.0) * t * (t - 2.0) / 2.0,
            (t + 1.0) * t * (t - 1.0) / 6.0,
        ];
        v[0] * w[0] + v[1] * w[1] + v[2] * w[2] + v[3] * w[3]
    }

    /// Re q_R, the phase rate taken out of [`Table::shifted`].
    pub fn phase(&self) -> f64 {
        self.phase
    }

    /// W(x) (x ≤ [`Table::covered`]).
    pub fn at(&self, x: f64) -> C {
        self.shifted(x) * C::from_polar(1.0, -self.phase * x)
    }
}

/// max over j of |Re Δ⁴v_j| + |Im Δ⁴v_j|.
fn largest_fourth_difference(v: &[C]) -> f64 {
    v.windows(5)
        .map(|w| {
            let d = w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4];
            d.re.abs() + d.im.abs()
        })
        .fold(0.0, f64::max)
}

/// The tables a caller keeps across runs, by soil (module docs, "Reuse").
#[derive(Clone, Debug, Default)]
pub struct Tables {
    tables: Vec<((u64, u64), Table)>,
}

impl Tables {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// The table of Poisson's ratio `nu` and damping ratio `xi`, covering `x_max`: the cached
    /// one (extended if needed) or a new one.
    pub fn get(&mut self, nu: f64, xi: f64, x_max: f64) -> Result<&Table> {
        let key = (nu.to_bits(), xi.to_bits());
        let at = match self.tables.iter().position(|(k, _)| *k == key) {
            Some(at) => at,
            None => {
                self.tables.push((key, Table::new(nu, xi)?));
                self.tables.len() - 1
            }
        };
        let table = &mut self.tables[at].1;
        table.cover(x_max)?;
        Ok(table)
    }

    /// The number of tables held.
    pub fn len(&self) -> usize {
        self.tables.len()
    }

    /// Whether no table is held.
    pub fn is_empty(&self) -> bool {
        self.tables.is_empty()
    }
}
