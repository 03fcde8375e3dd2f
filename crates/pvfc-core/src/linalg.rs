//! Small dense linear algebra that the control step needs at fixed size, without nalgebra's
//! general (pivoting, dynamically sized) loops.

use crate::Real;
use nalgebra::SMatrix;

/// The inverse of a symmetric positive definite `M×M` matrix `A`, by Cholesky: `A = L Lᵀ`,
/// `W = L⁻¹` (lower triangular, by forward substitution), `A⁻¹ = Wᵀ W`. Reads `A`'s lower
/// triangle and returns a symmetric matrix; `None` when a pivot is not > 0 (`A` not positive
/// definite, or NaN). About `M³/2` multiply-adds and `M` square roots, against LU with partial
/// pivoting's `M³` and its row swaps (nalgebra's `try_inverse` above 4×4).
#[inline]
pub fn spd_inverse<T: Real, const M: usize>(a: &SMatrix<T, M, M>) -> Option<SMatrix<T, M, M>> {
    // L's entries, then W's over them (W[i][j] needs L[i][j..i] and W[j..i][j] only).
    let mut l = [[T::zero(); M]; M];
    // 1 / L[j][j], which is also W[j][j].
    let mut inv_diag = [T::zero(); M];
    for j in 0..M {
        let row_j = l[j];
        let d = row_j[..j].iter().fold(a[(j, j)], |d, x| d - *x * *x);
        // NaN fails too.
        if d.partial_cmp(&T::zero()) != Some(core::cmp::Ordering::Greater) {
            return None;
        }
        let r = T::one() / d.sqrt();
        inv_diag[j] = r;
        for i in j + 1..M {
            let s = l[i][..j]
                .iter()
                .zip(&row_j[..j])
                .fold(a[(i, j)], |s, (x, y)| s - *x * *y);
            l[i][j] = s * r;
        }
    }
    // W = L⁻¹: W[j][j] = 1/L[j][j], W[i][j] = −(Σ_{j≤k<i} L[i][k] W[k][j]) / L[i][i].
    let mut w = [[T::zero(); M]; M];
    for j in 0..M {
        w[j][j] = inv_diag[j];
        for i in j + 1..M {
            let mut s = T::zero();
            for (x, row) in l[i][j..i].iter().zip(&w[j..i]) {
                s += *x * row[j];
            }
            w[i][j] = -s * inv_diag[i];
        }
    }
    // A⁻¹ = Wᵀ W: (A⁻¹)[i][j] = Σ_{k ≥ max(i, j)} W[k][i] W[k][j].
    let mut out = SMatrix::<T, M, M>::zeros();
    for i in 0..M {
        for j in 0..=i {
            let mut s = T::zero();
            for row in &w[i..] {
                s += row[i] * row[j];
            }
            out[(i, j)] = s;
            out[(j, i)] = s;
        }
    }
    Some(out)
}

/// `J Jᵀ + μ² I` for an `M×N` matrix `J` (the damped least squares' Gram matrix), its lower
/// triangle computed and mirrored: `M(M+1)/2` row products instead of `M²`.
#[inline]
pub fn damped_gram<T: Real, const M: usize, const N: usize>(
    j: &SMatrix<T, M, N>,
    mu2: T,
) -> SMatrix<T, M, M> {
    let mut out = SMatrix::<T, M, M>::zeros();
    for r in 0..M {
        for c in 0..=r {
            let mut s = T::zero();
            for k in 0..N {
                s += j[(r, k)] * j[(c, k)];
            }
            out[(r, c)] = s;
            out[(c, r)] = s;
        }
        out[(r, r)] += mu2;
    }
    out
}

#[cfg(test)]
#[allow(clippy::expect_used)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, SMatrix};

    /// `J Jᵀ + μ² I` of a fixed, full and a rank-deficient `J`: the inverse agrees with
    /// nalgebra's LU inverse to rounding, and `A A⁻¹ = I`.
    #[test]
    fn spd_inverse_inverts_damped_gram_matrices() {
        let j = SMatrix::<f64, 6, 7>::from_fn(|r, c| ((r * 7 + c) as f64 * 0.37).sin());
        for (mu, rank_one) in [(1e-2, false), (1e-3, false), (1e-2, true)] {
            let j = if rank_one { j.column(0) * j.row(1) } else { j };
            let a = j * j.transpose() + SMatrix::<f64, 6, 6>::identity() * (mu * mu);
            let inv = spd_inverse(&a).expect("positive definite");
            let lu = a.try_inverse().expect("invertible");
            // Both are backward stable: they agree to the condition number times ε.
            let eig = a.symmetric_eigenvalues();
            let cond = eig.max() / eig.min();
            let tol = cond * 1e-15;
            let scale = lu.abs().max();
            assert!(
                (inv - lu).abs().max() < tol * scale,
                "cond {cond:e}: {inv} vs {lu}"
            );
            let residual = (a * inv - SMatrix::<f64, 6, 6>::identity()).abs().max();
            assert!(residual < tol, "cond {cond:e}: |A A⁻¹ − I| = {residual:e}");
            assert_eq!(inv, inv.transpose());
        }
    }

    /// The Gram matrix against nalgebra's product, to rounding.
    #[test]
    fn damped_gram_is_j_jt_plus_mu2() {
        let j = SMatrix::<f64, 6, 7>::from_fn(|r, c| ((r * 7 + c) as f64 * 0.37).sin());
        let a = damped_gram(&j, 1e-4);
        let b = j * j.transpose() + SMatrix::<f64, 6, 6>::identity() * 1e-4;
        assert!((a - b).abs().max() < 1e-15, "{a} vs {b}");
        assert_eq!(a, a.transpose());
    }

    /// Not positive definite, or NaN: `None`.
    #[test]
    fn spd_inverse_refuses_what_is_not_positive_definite() {
        let indefinite = Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(spd_inverse(&indefinite).is_none());
        assert!(spd_inverse(&Matrix3::<f64>::zeros()).is_none());
        let mut nan = Matrix3::<f64>::identity();
        nan[(1, 1)] = f64::NAN;
        assert!(spd_inverse(&nan).is_none());
        let f32_inv = spd_inverse(&(Matrix3::<f32>::identity() * 4.0)).expect("definite");
        assert_eq!(f32_inv, Matrix3::identity() * 0.25);
    }
}
