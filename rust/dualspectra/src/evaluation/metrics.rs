//! Region scores: precision, recall and intersection over union (IoU) of a predicted
//! region $R$ against a ground-truth region $G$ on the same mesh, and the cumulative IoU
//! curve of a benchmark (the paper's Fig. 5 and Fig. 7).
//!
//! With a weight $w_i \ge 0$ per vertex and $|X| = \sum_{i \in X} w_i$:
//! $$P = \frac{|R \cap G|}{|R|}, \quad R_{ec} = \frac{|R \cap G|}{|G|}, \quad
//!   \mathrm{IoU} = \frac{|R \cap G|}{|R \cup G|}.$$
//! Vertex-count scores use $w_i = 1$; area-weighted scores use the lumped (barycentric)
//! vertex areas $w_i = a_i$ ([`crate::operators::lumped_mass`]), so they do not depend on
//! how densely each part is sampled. SHREC'16 and the paper (Table 1) report IoU.
//!
//! Empty sets: a ratio $0/0$ is 1 when both sets it compares are empty (an empty
//! prediction of an empty truth is perfect) and 0 otherwise.

use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use serde::{Deserialize, Serialize};

/// Precision, recall and IoU of one region against one ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    pub precision: f64,
    pub recall: f64,
    pub iou: f64,
}

fn ratio(num: f64, den: f64, both_empty: bool) -> f64 {
    if den > 0.0 {
        (num / den).clamp(0.0, 1.0)
    } else if both_empty {
        1.0
    } else {
        0.0
    }
}

fn check_len(what: &str, len: usize, n: usize) -> Result<()> {
    if len != n {
        return Err(Error::InvalidArgument(format!(
            "{what} has {len} entries, expected {n} (one per vertex)"
        )));
    }
    Ok(())
}

/// Scores with one weight per vertex (see the module doc). All three slices must have the
/// same length; weights must be finite and non-negative.
pub fn weighted_scores(region: &[bool], truth: &[bool], weights: &[f64]) -> Result<Scores> {
    let n = region.len();
    check_len("ground truth", truth.len(), n)?;
    check_len("weights", weights.len(), n)?;
    if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(Error::InvalidArgument(format!(
            "weight {i} is {} (must be finite and >= 0)",
            weights[i]
        )));
    }
    let (mut r, mut g, mut inter, mut union) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        let w = weights[i];
        if region[i] {
            r += w;
        }
        if truth[i] {
            g += w;
        }
        if region[i] && truth[i] {
            inter += w;
        }
        if region[i] || truth[i] {
            union += w;
        }
    }
    let (r_empty, g_empty) = (!(r > 0.0), !(g > 0.0));
    Ok(Scores {
        precision: ratio(inter, r, r_empty && g_empty),
        recall: ratio(inter, g, r_empty && g_empty),
        iou: ratio(inter, union, r_empty && g_empty),
    })
}

/// Scores by vertex counts ($w_i = 1$).
pub fn scores(region: &[bool], truth: &[bool]) -> Result<Scores> {
    weighted_scores(region, truth, &vec![1.0; region.len()])
}

/// Scores weighted by the lumped vertex areas of `mesh` (masks indexed by its vertices).
pub fn area_scores(mesh: &TriMesh, region: &[bool], truth: &[bool]) -> Result<Scores> {
    check_len("region", region.len(), mesh.n_vertices())?;
    weighted_scores(region, truth, &crate::operators::lumped_mass(mesh))
}

/// Which ground truth a symmetry-aware score picked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Match {
    Direct,
    Symmetric,
}

/// Symmetry-aware scores: the better (by IoU, ties to the direct one) of the scores against
/// `truth` and against its left-right mirror `truth_sym`, as SHREC'16 accepts a symmetric match.
pub fn symmetry_aware(
    region: &[bool],
    truth: &[bool],
    truth_sym: &[bool],
    weights: Option<&[f64]>,
) -> Result<(Scores, Match)> {
    let ones;
    let w = match weights {
        Some(w) => w,
        None => {
            ones = vec![1.0; region.len()];
            &ones
        }
    };
    let direct = weighted_scores(region, truth, w)?;
    let sym = weighted_scores(region, truth_sym, w)?;
    Ok(if sym.iou > direct.iou {
        (sym, Match::Symmetric)
    } else {
        (direct, Match::Direct)
    })
}

/// Cumulative IoU of a benchmark: $c(x) = \#\{j : \mathrm{IoU}_j \ge x\} / n$ for
/// $x \in [0, 1]$, a non-increasing step function (paper Fig. 5). Its integral over
/// $[0, 1]$ is the mean IoU (the paper: "areas under the curves are the mean IoUs").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CumulativeIou {
    /// The IoUs, clamped to [0, 1], sorted ascending.
    pub sorted: Vec<f64>,
}

impl CumulativeIou {
    /// Fraction of pairs with IoU `>= x` (1 for `x <= 0` unless empty; 0 for an empty set).
    pub fn fraction_at_least(&self, x: f64) -> f64 {
        if self.sorted.is_empty() {
            return 0.0;
        }
        let below = self.sorted.partition_point(|&v| v < x);
        (self.sorted.len() - below) as f64 / self.sorted.len() as f64
    }
    /// `n + 1 >= 2` evenly spaced samples `(x, c(x))` over [0, 1], for plotting.
    pub fn samples(&self, n: usize) -> Vec<(f64, f64)> {
        let n = n.max(1);
        (0..=n)
            .map(|i| {
                let x = i as f64 / n as f64;
                (x, self.fraction_at_least(x))
            })
            .collect()
    }
    /// The exact step curve as corner points `(x, c(x))`, from (0, 1) to (1, c(1)), for plotting.
    pub fn steps(&self) -> Vec<(f64, f64)> {
        let mut pts = vec![(0.0, self.fraction_at_least(0.0))];
        let mut distinct = self.sorted.clone();
        distinct.dedup();
        for &v in &distinct {
            let before = self.fraction_at_least(v);
            let after = self.fraction_at_least(v + f64::EPSILON.max(v * f64::EPSILON));
            pts.push((v, before));
            if after != before {
                pts.push((v, after));
            }
        }
        // Close the curve at x = 1 unless an IoU of exactly 1 already put the corner there.
        if pts.last().is_none_or(|p| p.0 < 1.0) {
            pts.push((1.0, self.fraction_at_least(1.0)));
        }
        pts
    }
    /// $\int_0^1 c(x)\,dx$, exactly (equals the mean of the clamped IoUs).
    pub fn area(&self) -> f64 {
        if self.sorted.is_empty() {
            return 0.0;
        }
        // c(x) = #{IoU_j >= x}/n, so its integral is sum_j IoU_j / n.
        self.sorted.iter().sum::<f64>() / self.sorted.len() as f64
    }
}

/// Build the cumulative IoU curve of a set of per-pair IoUs (non-finite values count as 0).
pub fn cumulative_iou(ious: &[f64]) -> CumulativeIou {
    let mut sorted: Vec<f64> = ious
        .iter()
        .map(|&v| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
        .collect();
    sorted.sort_by(|a, b| a.total_cmp(b));
    CumulativeIou { sorted }
}

/// Mean of `values` (0 for an empty slice).
pub fn mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        0.0
    } else {
        values.iter().sum::<f64>() / values.len() as f64
    }
}

/// Median of `values` (0 for an empty slice; mean of the two middle values for even lengths).
pub fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;

    /// Deterministic pseudo-random masks (xorshift), so the laws are checked on many inputs.
    fn masks(n: usize, seed: u64) -> (Vec<bool>, Vec<bool>) {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let a = (0..n).map(|_| next() % 3 == 0).collect();
        let b = (0..n).map(|_| next() % 2 == 0).collect();
        (a, b)
    }

    #[test]
    fn iou_of_a_region_with_itself_is_one() {
        for seed in 1..20 {
            let (r, _) = masks(200, seed);
            let s = scores(&r, &r).unwrap();
            assert_eq!((s.precision, s.recall, s.iou), (1.0, 1.0, 1.0));
        }
    }

    #[test]
    fn iou_is_symmetric_and_precision_recall_swap() {
        for seed in 1..20 {
            let (r, g) = masks(300, seed);
            let a = scores(&r, &g).unwrap();
            let b = scores(&g, &r).unwrap();
            assert_eq!(a.iou, b.iou);
            assert_eq!(a.precision, b.recall);
            assert_eq!(a.recall, b.precision);
            // IoU <= min(P, R) and IoU = 1 / (1/P + 1/R - 1) when both positive.
            assert!(a.iou <= a.precision.min(a.recall) + 1e-15);
            if a.precision > 0.0 && a.recall > 0.0 {
                let from_pr = 1.0 / (1.0 / a.precision + 1.0 / a.recall - 1.0);
                assert!((from_pr - a.iou).abs() <= 8.0 * f64::EPSILON);
            }
        }
    }

    #[test]
    fn disjoint_regions_score_zero() {
        let r: Vec<bool> = (0..100).map(|i| i < 40).collect();
        let g: Vec<bool> = (0..100).map(|i| i >= 60).collect();
        let s = scores(&r, &g).unwrap();
        assert_eq!((s.precision, s.recall, s.iou), (0.0, 0.0, 0.0));
    }

    #[test]
    fn empty_sets() {
        let e = vec![false; 10];
        let full = vec![true; 10];
        assert_eq!(scores(&e, &e).unwrap().iou, 1.0);
        let s = scores(&e, &full).unwrap();
        assert_eq!((s.precision, s.recall, s.iou), (0.0, 0.0, 0.0));
    }

    #[test]
    fn uniform_weights_equal_counts_and_scale_does_not_matter() {
        for seed in 1..10 {
            let (r, g) = masks(150, seed);
            let c = scores(&r, &g).unwrap();
            for w in [1e-8, 0.37, 1e8] {
                let s = weighted_scores(&r, &g, &vec![w; 150]).unwrap();
                assert!((s.iou - c.iou).abs() <= 4.0 * f64::EPSILON);
                assert!((s.precision - c.precision).abs() <= 4.0 * f64::EPSILON);
                assert!((s.recall - c.recall).abs() <= 4.0 * f64::EPSILON);
            }
        }
    }

    #[test]
    fn area_scores_on_a_half_sphere_match_the_area_ratio() {
        // R = upper hemisphere vertices, G = all: precision 1, recall = IoU = area fraction ~ 1/2.
        let m = generate::icosphere(3);
        let r: Vec<bool> = m.vertices().iter().map(|p| p[2] > 0.0).collect();
        let g = vec![true; m.n_vertices()];
        let s = area_scores(&m, &r, &g).unwrap();
        assert_eq!(s.precision, 1.0);
        assert!((s.iou - 0.5).abs() < 0.03, "{}", s.iou);
        assert_eq!(s.iou, s.recall);
    }

    #[test]
    fn bad_inputs_are_errors() {
        assert!(scores(&[true], &[true, false]).is_err());
        assert!(weighted_scores(&[true], &[true], &[-1.0]).is_err());
        assert!(weighted_scores(&[true], &[true], &[f64::NAN]).is_err());
    }

    #[test]
    fn symmetry_aware_takes_the_better_match() {
        let (r, g) = masks(100, 3);
        let (s, m) = symmetry_aware(&r, &g, &r, None).unwrap();
        assert_eq!((s.iou, m), (1.0, Match::Symmetric));
        let (s, m) = symmetry_aware(&r, &r, &g, None).unwrap();
        assert_eq!((s.iou, m), (1.0, Match::Direct));
    }

    #[test]
    fn cumulative_curve_area_is_the_mean_iou() {
        let ious = [0.1, 0.5, 0.5, 0.9, 1.0, 0.0, 0.73];
        let c = cumulative_iou(&ious);
        assert!((c.area() - mean(&ious)).abs() <= 4.0 * f64::EPSILON);
        // Riemann sum of the step function converges to the same area.
        let n = 100_000;
        let riemann: f64 = (0..n)
            .map(|i| c.fraction_at_least((i as f64 + 0.5) / n as f64))
            .sum::<f64>()
            / n as f64;
        assert!((riemann - c.area()).abs() < 1e-4);
        assert_eq!(c.fraction_at_least(0.0), 1.0);
        assert_eq!(c.fraction_at_least(0.5), 5.0 / 7.0);
        // Non-increasing.
        let s = c.samples(50);
        assert!(s.windows(2).all(|w| w[1].1 <= w[0].1));
        let st = c.steps();
        assert!(st.windows(2).all(|w| w[1].0 >= w[0].0 && w[1].1 <= w[0].1));
    }

    #[test]
    fn mean_and_median() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
        assert_eq!(mean(&[1.0, 2.0]), 1.5);
    }
}
