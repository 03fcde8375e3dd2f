//! The navigation function of SO(3), eq. (26).

use super::{NavigationFunction, NavigationSample};
use crate::error::{Error, ErrorKind, Result};
use crate::lie::{hat, vee, So3, Tangent};
use crate::scalar::cast;
use crate::Real;
use nalgebra::Matrix3;

/// `U(E) = tr(P (I − E)) / π'` on SO(3) (eq. 26), `π' = π₂ + π₃ − π₁`, with the metric
/// `⟨⟨ω̂₁, ω̂₂⟩⟩_V = tr(ω̂₁ᵀ ω̂₂) = 2 ω₁ᵀω₂` of section IV-B, for which
/// `grad U(E) = E ω̂`, `ω̂ = (PE − EᵀP)/(2π')`, i.e. `grad U = vee(PE)/π'` in body coordinates
/// (`= (EPE − P)/(2π')` as a matrix, as in the paper).
///
/// # Conditions on P
/// `P` must be symmetric with distinct eigenvalues `π₁ < π₂ < π₃` (non-degenerate critical
/// points). The paper also asks `(π₁+π₂)(π₁+π₃)(π₂+π₃) ≠ 0`; for the identity to be the unique
/// minimum with value 0 (Definition 1) one needs the stronger `π₁ + π₂ > 0`: the Hessian at
/// `I` is `(tr P·I − P)/(2π')` in body coordinates, with eigenvalues `(π_j + π_k)/(2π')`, and
/// the other three critical points (half-turns about the eigenvectors) have
/// `U = 2(tr P − π_i)/π'`. This constructor enforces the stronger condition.
///
/// ```
/// use pvfc_core::navigation::So3Navigation;
/// use nalgebra::Matrix3;
/// assert!(So3Navigation::new(Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 2.0, 3.0))).is_ok());
/// // equal eigenvalues: degenerate critical points
/// let err = So3Navigation::new(Matrix3::<f64>::identity()).unwrap_err();
/// assert_eq!(err.kind(), pvfc_core::ErrorKind::InvalidNavigationMatrix);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct So3Navigation<T: Real> {
    p: Matrix3<T>,
    inv_pi_prime: T,
    eigenvalues: [T; 3],
}

impl<T: Real> So3Navigation<T> {
    /// Validates `P` (see the type's documentation) and builds the navigation function.
    pub fn new(p: Matrix3<T>) -> Result<Self> {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(Error::new(ErrorKind::NonFinite, "So3Navigation: P"));
        }
        let tol = T::default_epsilon().sqrt() * p.norm();
        if (p - p.transpose()).norm() > tol {
            return Err(Error::new(
                ErrorKind::InvalidNavigationMatrix,
                "So3Navigation: P must be symmetric",
            ));
        }
        let sym = (p + p.transpose()) * cast::<T>(0.5);
        let ev = sym.symmetric_eigenvalues();
        let mut e = [ev[0], ev[1], ev[2]];
        e.sort_unstable_by(|a, b| a.partial_cmp(b).unwrap_or(core::cmp::Ordering::Equal));
        if e[1] - e[0] <= tol || e[2] - e[1] <= tol {
            return Err(Error::new(
                ErrorKind::InvalidNavigationMatrix,
                "So3Navigation: eigenvalues of P must be distinct (π₁ < π₂ < π₃)",
            ));
        }
        if e[0] + e[1] <= tol {
            return Err(Error::new(
                ErrorKind::InvalidNavigationMatrix,
                "So3Navigation: need π₁ + π₂ > 0 for a unique minimum at the identity",
            )
            .with_value(nalgebra::try_convert::<T, f64>(e[0] + e[1]).unwrap_or(f64::NAN)));
        }
        let pi_prime = e[1] + e[2] - e[0];
        Ok(So3Navigation {
            p: sym,
            inv_pi_prime: T::one() / pi_prime,
            eigenvalues: e,
        })
    }

    /// The matrix `P`.
    pub fn matrix(&self) -> &Matrix3<T> {
        &self.p
    }

    /// The eigenvalues `π₁ < π₂ < π₃` of `P`.
    pub fn eigenvalues(&self) -> [T; 3] {
        self.eigenvalues
    }
}

impl<T: Real> NavigationFunction<T, So3<T>, 3> for So3Navigation<T> {
    #[inline]
    fn evaluate(&self, e: &So3<T>, e_rate: &Tangent<T, 3>) -> NavigationSample<T, 3> {
        let pe = self.p * e.matrix();
        let value = (self.p.trace() - pe.trace()) * self.inv_pi_prime;
        let gradient = vee(&pe) * self.inv_pi_prime;
        let differential = gradient * cast::<T>(2.0);
        let gradient_rate = vee(&(pe * hat(e_rate))) * self.inv_pi_prime;
        NavigationSample {
            value,
            value_rate: differential.dot(e_rate),
            differential,
            gradient,
            gradient_rate,
        }
    }

    #[inline]
    fn metric_weight(&self) -> T {
        cast(2.0)
    }
}
