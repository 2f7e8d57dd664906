//! The evaluation's metrics on motions and classifier features, and their confidence intervals.
//!
//! - [`geodesic`]: mean angle (radians) between two motions' local joint rotations,
//!   `acos((tr(R₁R₂ᵀ) − 1) / 2)`, over frames and the 21 joints.
//! - [`foot_skate`]: mean horizontal speed (cm/s) of the feet while they touch the floor.
//! - [`fid`]: Fréchet distance between two sets of feature vectors (Gaussian fits).
//! - [`mean_ci`]: mean and 95 % confidence half-width over repeats.

use glam::DVec3;
use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::Motion;
use crate::skeleton::canonical::{FPS, joint};

/// Foot joints whose sliding counts: ankles and toes, both sides.
pub const FOOT_JOINTS: [usize; 4] = [joint::FOOT_L, joint::TOES_L, joint::FOOT_R, joint::TOES_R];

/// A foot joint is in contact while it is within this height (cm) of its lowest point in the
/// clip, in two consecutive frames.
pub const CONTACT_HEIGHT_CM: f64 = 3.0;

/// Mean geodesic distance (radians, in `[0, π]`) between the local joint rotations of `a` and
/// `b`, frame by frame over their common length. `None` if either is empty.
pub fn geodesic(a: &Motion, b: &Motion) -> Option<f64> {
    let n = a.frames().min(b.frames());
    if n == 0 {
        return None;
    }
    let (mut sum, mut count) = (0.0, 0usize);
    for (pa, pb) in a.rotations().iter().zip(b.rotations()).take(n) {
        for (qa, qb) in pa.iter().zip(pb) {
            // |q₁·q₂| = cos(θ/2) for unit quaternions: θ = 2 acos |q₁·q₂|.
            sum += 2.0 * qa.dot(*qb).abs().min(1.0).acos();
            count += 1;
        }
    }
    Some(sum / count as f64)
}

/// Sum and count of the horizontal foot speeds (cm/s) of `m` during contact (see
/// [`CONTACT_HEIGHT_CM`]); add up over clips and divide for the pooled mean.
pub fn foot_skate_parts(m: &Motion) -> (f64, usize) {
    let positions = m.global_positions();
    let (mut sum, mut count) = (0.0, 0usize);
    for &j in &FOOT_JOINTS {
        let floor = positions.iter().map(|p| p[j].y).fold(f64::INFINITY, f64::min);
        for w in positions.windows(2) {
            let (p, q) = (w[0][j], w[1][j]);
            if p.y <= floor + CONTACT_HEIGHT_CM && q.y <= floor + CONTACT_HEIGHT_CM {
                sum += DVec3::new(q.x - p.x, 0.0, q.z - p.z).length() * FPS;
                count += 1;
            }
        }
    }
    (sum, count)
}

/// Mean horizontal foot speed during contact, cm/s, pooled over `motions`. `None` without contact.
pub fn foot_skate<'a>(motions: impl IntoIterator<Item = &'a Motion>) -> Option<f64> {
    let (sum, count) = motions.into_iter().map(foot_skate_parts).fold((0.0, 0), |(s, c), (s1, c1)| (s + s1, c + c1));
    (count > 0).then(|| sum / count as f64)
}

/// Mean joint distance (cm) between two motions in world space over their common length.
pub fn position_distance(a: &Motion, b: &Motion) -> Option<f64> {
    let (pa, pb) = (a.global_positions(), b.global_positions());
    let n = pa.len().min(pb.len());
    if n == 0 {
        return None;
    }
    let sum: f64 = pa.iter().zip(&pb).take(n).flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (*p - *q).length())).sum();
    Some(sum / (n * pa[0].len()) as f64)
}

/// Euclidean distance between two feature vectors.
pub fn feature_distance(a: &[f32], b: &[f32]) -> f64 {
    a.iter().zip(b).map(|(x, y)| f64::from(x - y).powi(2)).sum::<f64>().sqrt()
}

fn mean_and_covariance(set: &[Vec<f32>]) -> (DVector<f64>, DMatrix<f64>) {
    let d = set[0].len();
    let n = set.len();
    let x = DMatrix::from_fn(n, d, |i, j| f64::from(set[i][j]));
    let mean = DVector::from_fn(d, |j, _| x.column(j).mean());
    let mut centred = x;
    for mut row in centred.row_iter_mut() {
        row -= mean.transpose();
    }
    let cov = centred.transpose() * &centred / (n.saturating_sub(1).max(1) as f64);
    (mean, cov)
}

/// Square root of a symmetric positive semi-definite matrix (negative eigenvalues from rounding
/// are clamped to zero).
fn sqrt_psd(m: DMatrix<f64>) -> DMatrix<f64> {
    let eig = SymmetricEigen::new(m);
    let roots = eig.eigenvalues.map(|l| l.max(0.0).sqrt());
    &eig.eigenvectors * DMatrix::from_diagonal(&roots) * eig.eigenvectors.transpose()
}

/// Fréchet distance between Gaussians fitted to two sets of equal-length feature vectors:
/// `|μ₁ − μ₂|² + tr(Σ₁ + Σ₂ − 2 (Σ₁^½ Σ₂ Σ₁^½)^½)`. `None` if a set has fewer than 2 vectors or
/// the lengths differ.
pub fn fid(a: &[Vec<f32>], b: &[Vec<f32>]) -> Option<f64> {
    if a.len() < 2 || b.len() < 2 || a[0].len() != b[0].len() || a[0].is_empty() {
        return None;
    }
    if a.iter().chain(b).any(|v| v.len() != a[0].len()) {
        return None;
    }
    let (m1, c1) = mean_and_covariance(a);
    let (m2, c2) = mean_and_covariance(b);
    let s1 = sqrt_psd(c1.clone());
    let middle = &s1 * &c2 * &s1;
    let middle = (&middle + middle.transpose()) * 0.5;
    let cross: f64 = SymmetricEigen::new(middle).eigenvalues.iter().map(|l| l.max(0.0).sqrt()).sum();
    Some(((m1 - m2).norm_squared() + c1.trace() + c2.trace() - 2.0 * cross).max(0.0))
}

/// Mean of `values` and the half-width of its 95 % confidence interval (normal approximation,
/// `1.96 · s / √n`, `s` the sample standard deviation); the half-width is `None` for fewer than
/// two values. `None` for no values.
pub fn mean_ci(values: &[f64]) -> Option<(f64, Option<f64>)> {
    if values.is_empty() {
        return None;
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    if values.len() < 2 {
        return Some((mean, None));
    }
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    Some((mean, Some(1.96 * var.sqrt() / n.sqrt())))
}
