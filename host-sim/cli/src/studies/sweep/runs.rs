//! The runs of a sweep: the cartesian product of its axes, each run identified by its axis
//! values, and the deterministic 1/N of them that a shard runs.
//!
//! Why identity by values, not by position: a rerun, a shard on another machine and a merge
//! must agree on which run a record belongs to even when an axis gains values. The position in
//! the product only orders the rows of results.csv.

use super::spec::{Scalar, Spec};
use crate::{Error, Result};

/// One run of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// Its position in the product (the last axis varies fastest), from 0.
    pub index: usize,
    /// One value per axis, in the spec's axis order.
    pub values: Vec<Scalar>,
    /// `key=value,key=value` in axis order: the run's identity.
    pub id: String,
}

impl Run {
    /// The `--set` overrides of this run: the spec's fixed ones, then its axis values.
    pub fn sets(&self, spec: &Spec) -> Vec<String> {
        let mut s = spec.sets.clone();
        s.extend(
            spec.axes
                .iter()
                .zip(&self.values)
                .map(|(a, v)| format!("{}={}", a.key, v.toml())),
        );
        s
    }

    /// The file name of its record: the identity with unsafe characters replaced, and a hash
    /// of the exact identity so that two identities never share a file.
    pub fn file_name(&self) -> String {
        let safe: String = self
            .id
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '=' | '_') {
                    c
                } else {
                    '_'
                }
            })
            .take(120)
            .collect();
        format!("{safe}-{:016x}.json", fnv1a(self.id.as_bytes()))
    }
}

/// FNV-1a, 64 bit: a stable hash (std's hasher may change between releases).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Every run of the spec, in product order.
pub fn all(spec: &Spec) -> Vec<Run> {
    let n = spec.runs();
    (0..n)
        .map(|index| {
            let mut rest = index;
            let mut values = vec![Scalar::Int(0); spec.axes.len()];
            for (k, a) in spec.axes.iter().enumerate().rev() {
                values[k] = a.values[rest % a.values.len()].clone();
                rest /= a.values.len();
            }
            let id = spec
                .axes
                .iter()
                .zip(&values)
                .map(|(a, v)| format!("{}={}", a.key, v.cell()))
                .collect::<Vec<_>>()
                .join(",");
            Run { index, values, id }
        })
        .collect()
}

/// `--shard I/N`: shard I (from 1) of N.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// Parses `I/N` with 1 ≤ I ≤ N.
    pub fn parse(s: &str) -> Result<Self> {
        let bad = |why: &str| Error::invalid("--shard", format!("`{s}`: {why}"));
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| bad("expected I/N, e.g. 1/4"))?;
        let i: usize = i
            .trim()
            .parse()
            .map_err(|_| bad("I must be a whole number"))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| bad("N must be a whole number"))?;
        if n == 0 {
            return Err(bad("N must be at least 1"));
        }
        if i == 0 || i > n {
            return Err(bad(&format!("I must be from 1 to N = {n}")));
        }
        Ok(Shard { index: i, count: n })
    }

    /// Whether the run at `index` of the product is this shard's: every N-th run, so each
    /// shard gets its share of every axis (fast and slow runs alike).
    pub fn holds(&self, index: usize) -> bool {
        index % self.count == self.index - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> Spec {
        Spec::parse(
            "scenario='paper-4.2'\n[axes]\nspeed=[50.0,100.0,150.0]\nseed=[1,2]\n[reduce]\nquantities=['peak:midspan_z']",
        )
        .unwrap()
    }

    #[test]
    fn the_product_runs_the_last_axis_fastest() {
        let ids: Vec<String> = all(&spec()).into_iter().map(|r| r.id).collect();
        assert_eq!(
            ids,
            [
                "speed=50.0,seed=1",
                "speed=50.0,seed=2",
                "speed=100.0,seed=1",
                "speed=100.0,seed=2",
                "speed=150.0,seed=1",
                "speed=150.0,seed=2"
            ]
        );
        let r = &all(&spec())[3];
        assert_eq!(r.sets(&spec()), ["speed=100.0", "seed=2"]);
    }

    #[test]
    fn shards_partition_the_runs() {
        let runs = all(&spec());
        for n in 1..=7 {
            let mut seen = vec![0; runs.len()];
            for i in 1..=n {
                let s = Shard::parse(&format!("{i}/{n}")).unwrap();
                for r in &runs {
                    if s.holds(r.index) {
                        seen[r.index] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "{n}: {seen:?}");
        }
        for bad in ["0/2", "3/2", "1/0", "x", "1/x"] {
            let e = Shard::parse(bad).unwrap_err().to_string();
            assert!(e.starts_with("--shard"), "{e}");
        }
    }

    #[test]
    fn file_names_are_distinct_and_safe() {
        let a = Run {
            index: 0,
            values: vec![],
            id: "law=a/b".into(),
        };
        let b = Run {
            id: "law=a_b".into(),
            ..a.clone()
        };
        assert!(!a.file_name().contains('/'));
        assert_ne!(a.file_name(), b.file_name());
        // The FNV-1a test vector.
        assert_eq!(fnv1a(b"a"), 0xaf63dc4c8601ec8c);
    }
}
