//! [`Flexibility`]: a small span's Keff⁻¹ held densely, so that a Newton–Raphson iteration
//! answers the coupling loop's queries without solving the span (issue #9: "keep the
//! iterations off the full solve").
//!
//! Why: a step's displacement is linear in the wheel loads, d₁ = Keff⁻¹ r + Keff⁻¹ F (Eq. 19,
//! r the load-free right-hand side), and F lives on the DOFs of the few loaded elements (Eq.
//! 15). With d_free = Keff⁻¹ r solved once per step, a query at an element (Eq. 16) needs d₁
//! only on that element's 12 DOFs: d_free there plus Σ_j Z_ij F_j over the loaded DOFs j of
//! the same decoupled component (a straight span's axial, torsion and two bending families
//! do not couple, so Z is zero across them). The whole step is formed once, on commit, in the
//! span's modal coordinates ([`super::modal_basis`], where d_free also comes from). An
//! iteration then costs a few hundred
//! independent multiply-adds instead of a sparse substitution, which is a chain of dependent
//! ones (docs/performance.md).
//!
//! The columns are computed once per distinct span by solving Keff z_j = e_j with the span's
//! own factor; off-component entries come out exactly zero (the factor has no entries
//! between components). Dense storage is n² words, so it is built only for spans of at most
//! [`MAX_DOFS`] free DOFs (the §4.2 span has 119, a §5 girder of 16 elements 95); larger
//! spans keep one solve per iteration.

use super::banded::Components;

/// The largest span (free DOFs) given a dense flexibility: at most 1200² words (11.5 MB;
/// the blocks of the components hold less).
pub const MAX_DOFS: usize = 1200;

/// Keff⁻¹ as one dense block per decoupled component (module docs).
#[derive(Clone, Debug)]
pub struct Flexibility {
    n: usize,
    /// Component of each DOF and its index within the component.
    component: Vec<usize>,
    local: Vec<usize>,
    /// Per component: its DOFs (ascending) and its block of Keff⁻¹, column-major.
    members: Vec<Vec<usize>>,
    blocks: Vec<Vec<f64>>,
}

impl Flexibility {
    /// The inverse of a matrix with decoupled `components`, `solve` doing x ← A⁻¹ x. `None`
    /// above [`MAX_DOFS`].
    pub fn new(components: &Components, mut solve: impl FnMut(&mut [f64])) -> Option<Self> {
        let n = components.dofs();
        if n > MAX_DOFS {
            return None;
        }
        let mut x = vec![0.0; n];
        let blocks = components
            .members
            .iter()
            .map(|members| {
                let m = members.len();
                let mut block = vec![0.0; m * m];
                for (col, &j) in block.chunks_exact_mut(m).zip(members) {
                    x.fill(0.0);
                    x[j] = 1.0;
                    solve(&mut x);
                    for (b, &i) in col.iter_mut().zip(members) {
                        *b = x[i];
                    }
                }
                block
            })
            .collect();
        Some(Flexibility {
            n,
            component: components.component.clone(),
            local: components.local.clone(),
            members: components.members.clone(),
            blocks,
        })
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.n
    }

    /// Stored values.
    pub fn stored(&self) -> usize {
        self.blocks.iter().map(Vec::len).sum()
    }

    /// Entry (i, j) of Keff⁻¹ (zero across components).
    pub fn entry(&self, i: usize, j: usize) -> f64 {
        let c = self.component[j];
        if self.component[i] != c {
            return 0.0;
        }
        self.blocks[c][self.local[j] * self.members[c].len() + self.local[i]]
    }

    /// d₁ at DOF `i`: `free[i] + Σ_j Z_ij load[j]`, the sum over the loaded DOFs of i's
    /// component in the order they were added, then added to `free[i]`.
    pub fn response_at(&self, support: &LoadSupport, free: &[f64], load: &[f64], i: usize) -> f64 {
        self.response_with(support, free[i], load, i)
    }

    /// [`Self::response_at`] with the free response at DOF `i` given as `free_i`.
    pub fn response_with(&self, support: &LoadSupport, free_i: f64, load: &[f64], i: usize) -> f64 {
        let c = self.component[i];
        let (block, m, il) = (&self.blocks[c], self.members[c].len(), self.local[i]);
        let mut acc = 0.0;
        for &(j, jl) in &support.lists[c] {
            acc += block[jl * m + il] * load[j];
        }
        free_i + acc
    }
}

/// The loaded DOFs of one span's current iteration, per component, each once, in the order
/// first loaded (global and in-component index). Capacity is reserved up front, so adding
/// never allocates.
#[derive(Clone, Debug)]
pub struct LoadSupport {
    lists: Vec<Vec<(usize, usize)>>,
    marked: Vec<bool>,
    len: usize,
}

impl LoadSupport {
    /// Empty, for a span with flexibility `flex`.
    pub fn new(flex: &Flexibility) -> Self {
        LoadSupport {
            lists: flex
                .members
                .iter()
                .map(|m| Vec::with_capacity(m.len()))
                .collect(),
            marked: vec![false; flex.n],
            len: 0,
        }
    }

    /// Number of loaded DOFs.
    pub fn len(&self) -> usize {
        self.len
    }

    /// No loaded DOF.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Forget every DOF: O(loaded DOFs).
    pub fn clear(&mut self) {
        for list in &mut self.lists {
            for &(j, _) in list.iter() {
                self.marked[j] = false;
            }
            list.clear();
        }
        self.len = 0;
    }

    /// Set the loaded DOFs of `load` to zero (every non-zero of a load vector built with
    /// this support).
    pub fn zero(&self, load: &mut [f64]) {
        for list in &self.lists {
            for &(j, _) in list {
                load[j] = 0.0;
            }
        }
    }

    /// The loaded DOFs, component by component, each in the order first loaded.
    pub fn dofs(&self) -> impl Iterator<Item = usize> + '_ {
        self.lists.iter().flat_map(|l| l.iter().map(|&(j, _)| j))
    }

    /// Record DOF `j` as loaded (once).
    pub fn add(&mut self, flex: &Flexibility, j: usize) {
        if !self.marked[j] {
            self.marked[j] = true;
            self.lists[flex.component[j]].push((j, flex.local[j]));
            self.len += 1;
        }
    }
}

/// The rows of Keff⁻¹ at a few DOFs (the loaded elements' own) over the current load
/// support, gathered once per step, so each iteration's [`Flexibility::response_at`] at those
/// DOFs is a dot product over contiguous memory: the same products in the same order, so
/// the same bits. Storage is reserved up front ([`HotRows::CAP`] values); a support too
/// large for it is refused and the caller keeps `response_at`.
#[derive(Clone, Debug)]
pub struct HotRows {
    /// Per DOF: its free index (`None` where supported), the offset of its row in `rows`
    /// and of its component's loads in `loads`, and the row's length.
    index: Vec<(Option<usize>, usize, usize, usize)>,
    rows: Vec<f64>,
    /// The loads of the support, component by component in list order; `offsets[c]` where
    /// component c's start.
    loads: Vec<f64>,
    offsets: Vec<usize>,
    ok: bool,
}

impl HotRows {
    /// Values reserved for the rows.
    pub const CAP: usize = 4096;

    /// Empty, for spans with flexibility `flex` and at most `dofs` hot DOFs.
    pub fn new(flex: &Flexibility, dofs: usize) -> Self {
        HotRows {
            index: Vec::with_capacity(dofs),
            rows: Vec::with_capacity(Self::CAP),
            loads: Vec::with_capacity(flex.n),
            offsets: vec![0; flex.members.len()],
            ok: false,
        }
    }

    /// Gather the rows of the DOFs `dofs` (free indices, `None` for a supported DOF) over
    /// `support`; unusable ([`Self::is_ready`] false) if they would exceed the storage.
    pub fn build(
        &mut self,
        flex: &Flexibility,
        support: &LoadSupport,
        dofs: impl Iterator<Item = Option<usize>>,
    ) {
        self.index.clear();
        self.rows.clear();
        let mut next = 0;
        for (c, list) in support.lists.iter().enumerate() {
            self.offsets[c] = next;
            next += list.len();
        }
        self.ok = false;
        for i in dofs {
            if self.index.len() == self.index.capacity() {
                return;
            }
            let Some(i) = i else {
                self.index.push((None, 0, 0, 0));
                continue;
            };
            let c = flex.component[i];
            let list = &support.lists[c];
            if self.rows.len() + list.len() > Self::CAP {
                return;
            }
            let (block, m, il) = (&flex.blocks[c], flex.members[c].len(), flex.local[i]);
            self.index
                .push((Some(i), self.rows.len(), self.offsets[c], list.len()));
            self.rows
                .extend(list.iter().map(|&(_, jl)| block[jl * m + il]));
        }
        self.ok = true;
    }

    /// Built and usable.
    pub fn is_ready(&self) -> bool {
        self.ok
    }

    /// The k-th value of `out` (its elements' DOFs in order) = [`Flexibility::response_at`]
    /// at the k-th DOF of [`Self::build`] (0 where supported), for this iteration's `load` on
    /// the same support.
    pub fn eval<'a>(
        &mut self,
        support: &LoadSupport,
        free: &[f64],
        load: &[f64],
        out: impl Iterator<Item = &'a mut f64>,
    ) {
        self.loads.clear();
        for list in &support.lists {
            self.loads.extend(list.iter().map(|&(j, _)| load[j]));
        }
        for (o, &(i, row, at, len)) in out.zip(&self.index) {
            let Some(i) = i else {
                *o = 0.0;
                continue;
            };
            let mut acc = 0.0;
            for (z, l) in self.rows[row..row + len]
                .iter()
                .zip(&self.loads[at..at + len])
            {
                acc += z * l;
            }
            *o = free[i] + acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::fe::assembly::SpanModel;
    use crate::physics::fe::cholesky::SparseCholesky;
    use crate::physics::guideway::BeamSection;

    /// On the §4.2 span's effective stiffness: the columns are Keff⁻¹'s (Keff·Z = I to
    /// round-off), zero across components, and free + Z·F equals faer's solve of
    /// Keff d = Keff·free + F to round-off at every DOF.
    #[test]
    fn columns_invert_and_responses_match_a_solve() {
        let model = SpanModel::new(&BeamSection::paper_4_2(), 25.0, 20).unwrap();
        let dt = 1e-3;
        let keff = model.k.combine(1.0, &model.m, 4.0 / (dt * dt));
        let n = keff.nrows();
        let faer = SparseCholesky::new(&keff).unwrap();
        let mut scratch = faer.scratch();
        let components = keff.components();
        assert_eq!(components.members.len(), 4);
        let flex = Flexibility::new(&components, |x| faer.solve_in_place(x, &mut scratch)).unwrap();
        let dense = keff.to_dense();
        let z = nalgebra::DMatrix::from_fn(n, n, |i, j| flex.entry(i, j));
        let mut x = vec![0.0; n];
        for j in 0..n {
            // Each column is the solve of the unit vector, whose entries in other components
            // come out exactly zero (as the block storage assumes).
            x.fill(0.0);
            x[j] = 1.0;
            faer.solve_in_place(&mut x, &mut scratch);
            for i in 0..n {
                assert_eq!(z[(i, j)], x[i], "({i}, {j})");
            }
        }
        let identity = &dense * &z;
        for ((i, j), v) in (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .zip(identity.iter())
        {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((v - want).abs() < 1e-9, "(K Z)[{i}, {j}] = {v}");
        }
        // Loads on two elements' DOFs (the §4.2 car's two axles), a free response.
        let mut support = LoadSupport::new(&flex);
        let mut load = vec![0.0; n];
        for (x, fz) in [(4.3, -3.7e4), (19.3, -3.6e4)] {
            let (e, shape) = model.shape_at(x, 1.5, 0.6).unwrap();
            model.add_shaped_force(e, &shape, 2.0e3, fz, &mut load, |j| support.add(&flex, j));
        }
        assert!(support.len() > 12 && support.len() <= 24);
        let free: Vec<f64> = (0..n).map(|i| 1e-4 * ((i as f64) * 0.37).sin()).collect();
        let mut rhs = nalgebra::DVector::from_column_slice(&free);
        rhs = &dense * rhs + nalgebra::DVector::from_column_slice(&load);
        let mut want = rhs.as_slice().to_vec();
        faer.solve_in_place(&mut want, &mut scratch);
        let peak = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, want) in want.iter().enumerate() {
            let got = flex.response_at(&support, &free, &load, i);
            assert!((got - want).abs() <= 1e-12 * peak, "{i}");
        }
        // The gathered rows give response_at's bits at two elements' DOFs.
        let dofs: Vec<Option<usize>> = [3usize, 15]
            .iter()
            .flat_map(|&e| model.element_free(e).to_vec())
            .collect();
        let mut rows = HotRows::new(&flex, dofs.len());
        rows.build(&flex, &support, dofs.iter().copied());
        assert!(rows.is_ready());
        let mut out = vec![f64::NAN; dofs.len()];
        rows.eval(&support, &free, &load, out.iter_mut());
        for (o, d) in out.iter().zip(&dofs) {
            let want = d.map_or(0.0, |i| flex.response_at(&support, &free, &load, i));
            assert_eq!(o.to_bits(), want.to_bits());
        }
        support.clear();
        assert!(support.is_empty());
        for (i, &free_i) in free.iter().enumerate() {
            assert_eq!(flex.response_at(&support, &free, &load, i), free_i);
        }
    }
}
