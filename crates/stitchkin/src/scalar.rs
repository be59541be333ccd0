//! The scalar type the engine computes with.
//!
//! Every position routine is generic over [`Real`], so one closed-form code
//! path yields plain positions (`f64`) and exact first and second analogs
//! (`Dual2_64`: value, d/dφ, d²/dφ²), and later exact derivatives with
//! respect to parameters.

use nalgebra::RealField;
use num_dual::{Dual2_64, Dual64};

/// A real number, or a dual number carrying exact derivatives.
pub trait Real: RealField + Copy + std::fmt::Debug + Send + Sync + 'static {
    /// A constant (all derivative parts zero).
    fn cst(x: f64) -> Self;
    /// The value part.
    fn re(self) -> f64;
    /// `x` as the independent variable φ: derivative parts seeded with 1
    /// (for `f64`, just `x`).
    fn var(x: f64) -> Self;
    /// `self · k` for a plain number `k` (cheaper than a dual product).
    fn times(self, k: f64) -> Self;
    /// `self` with the sign of `sign` (an assembly branch, ±1).
    #[inline(always)]
    fn signed(self, sign: f64) -> Self {
        if sign < 0.0 { -self } else { self }
    }
}

impl Real for f64 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn re(self) -> f64 {
        self
    }
    #[inline(always)]
    fn var(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn times(self, k: f64) -> Self {
        self * k
    }
}

impl Real for Dual2_64 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Dual2_64::from_re(x)
    }
    #[inline(always)]
    fn re(self) -> f64 {
        self.re
    }
    #[inline(always)]
    fn var(x: f64) -> Self {
        Dual2_64::new(x, 1.0, 0.0)
    }
    #[inline(always)]
    fn times(self, k: f64) -> Self {
        Dual2_64::new(self.re * k, self.v1 * k, self.v2 * k)
    }
}

impl Real for Dual64 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Dual64::from_re(x)
    }
    #[inline(always)]
    fn re(self) -> f64 {
        self.re
    }
    #[inline(always)]
    fn var(x: f64) -> Self {
        Dual64::new(x, 1.0)
    }
    #[inline(always)]
    fn times(self, k: f64) -> Self {
        Dual64::new(self.re * k, self.eps * k)
    }
}

/// First and second derivatives of a `Dual2_64` value: (value, d/dφ, d²/dφ²).
#[inline]
pub fn parts(x: Dual2_64) -> [f64; 3] {
    [x.re, x.v1, x.v2]
}

/// The independent variable φ (rad) as a second-order dual number.
#[inline]
pub fn phi_dual(phi_rad: f64) -> Dual2_64 {
    Dual2_64::new(phi_rad, 1.0, 0.0)
}
