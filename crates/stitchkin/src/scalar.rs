//! The scalar type the engine computes with.
//!
//! Every position routine is generic over [`Real`], so one closed-form code
//! path yields plain positions (`f64`) and exact first and second analogs
//! (`Dual2_64`: value, d/dφ, d²/dφ²), and exact first derivatives with
//! respect to parameters (`Dual64`, used by `study::sensitivity`).

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
    /// `self · k` where `k` is a constant of the cycle (a link length, an
    /// offset): the cheap product when `k` carries no derivatives, as in
    /// φ-analogs; the full product otherwise (parameter sensitivities).
    fn times_k(self, k: Self) -> Self;
    /// The first derivative part (d/dφ for φ-analogs; 0 for `f64`).
    #[inline(always)]
    fn d1(self) -> f64 {
        0.0
    }
    /// The second derivative part (0 for `f64` and first-order duals).
    #[inline(always)]
    fn d2(self) -> f64 {
        0.0
    }
    /// A number with value `re` and φ-derivatives `d1`, `d2` (the parts a
    /// type cannot carry are dropped: `f64` keeps `re`, `Dual64` `re, d1`).
    fn from_parts(re: f64, d1: f64, d2: f64) -> Self;
    /// `self` with the sign of `sign` (an assembly branch, ±1).
    #[inline(always)]
    fn signed(self, sign: f64) -> Self {
        if sign < 0.0 { -self } else { self }
    }

    /// The angle of the vector (x, y) = (`x`, `self`), like `atan2`, with
    /// derivatives that stay finite wherever the direction is defined.
    /// (num-dual's `atan2` differentiates `atan(y/x)`, which is NaN when x is
    /// exactly 0.) Written as θ0 + atan(y'/x') with (x', y') the vector turned
    /// back by its own angle θ0, so x' = |(x, y)| > 0.
    /// Replaces every element by its square root (a loop the compiler
    /// vectorises inside a `widest!` function); the thread paths take a
    /// cycle's square roots this way.
    #[inline(always)]
    fn sqrt_slice(x: &mut [Self]) {
        for v in x {
            *v = v.sqrt();
        }
    }

    #[inline]
    fn angle_of(self, x: Self) -> Self {
        let y = self;
        let th0 = y.re().atan2(x.re());
        let (s, c) = th0.sin_cos();
        let (xr, yr) = (x * Self::cst(c) + y * Self::cst(s), y * Self::cst(c) - x * Self::cst(s));
        Self::cst(th0) + (yr / xr).atan()
    }
}

impl Real for f64 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn from_parts(re: f64, _d1: f64, _d2: f64) -> Self {
        re
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
    #[inline(always)]
    fn times_k(self, k: Self) -> Self {
        self * k
    }
    #[inline(always)]
    fn angle_of(self, x: Self) -> Self {
        self.atan2(x)
    }
}

impl Real for Dual2_64 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Dual2_64::from_re(x)
    }
    #[inline(always)]
    fn from_parts(re: f64, d1: f64, d2: f64) -> Self {
        Dual2_64::new(re, d1, d2)
    }
    #[inline(always)]
    fn d1(self) -> f64 {
        self.v1
    }
    #[inline(always)]
    fn d2(self) -> f64 {
        self.v2
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
    #[inline(always)]
    fn times_k(self, k: Self) -> Self {
        if k.v1 == 0.0 && k.v2 == 0.0 {
            self.times(k.re)
        } else {
            self * k
        }
    }
}

impl Real for Dual64 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Dual64::from_re(x)
    }
    #[inline(always)]
    fn from_parts(re: f64, d1: f64, _d2: f64) -> Self {
        Dual64::new(re, d1)
    }
    #[inline(always)]
    fn d1(self) -> f64 {
        self.eps
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
    #[inline(always)]
    fn times_k(self, k: Self) -> Self {
        if k.eps == 0.0 { self.times(k.re) } else { self * k }
    }
}

/// The vector unit the engine's cycle loops are compiled for (see
/// `widest!`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum VectorUnit {
    Baseline,
    Avx2,
    Avx512,
}

/// The widest vector unit this CPU has (read once). The environment
/// variable `STITCHKIN_SIMD` = `baseline`, `avx2` or `avx512` caps it, for
/// benchmarks and for ruling the vector units out when chasing a problem.
pub fn vector_unit() -> VectorUnit {
    static UNIT: std::sync::OnceLock<VectorUnit> = std::sync::OnceLock::new();
    *UNIT.get_or_init(|| {
        #[allow(unused_mut)]
        let mut has = VectorUnit::Baseline;
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                has = VectorUnit::Avx512;
            } else if std::arch::is_x86_feature_detected!("avx2") {
                has = VectorUnit::Avx2;
            }
        }
        let cap = match std::env::var("STITCHKIN_SIMD").ok().as_deref() {
            Some("baseline") => VectorUnit::Baseline,
            Some("avx2") => VectorUnit::Avx2,
            _ => VectorUnit::Avx512,
        };
        has.min(cap)
    })
}

/// [`widest!`] for a free function: `$name` runs `$inner` (an
/// `#[inline(always)]` function, or a path to one, with the same
/// arguments) compiled for the widest vector unit.
macro_rules! widest_fn {
    ($(#[$meta:meta])* $vis:vis fn $name:ident<$($g:ident: $bound:path),*>($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? => $inner:expr) => {
        $(#[$meta])*
        $vis fn $name<$($g: $bound),*>($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx512f")]
                fn avx512<$($g: $bound),*>($($arg: $ty),*) $(-> $ret)? {
                    $inner($($arg),*)
                }
                #[target_feature(enable = "avx2")]
                fn avx2<$($g: $bound),*>($($arg: $ty),*) $(-> $ret)? {
                    $inner($($arg),*)
                }
                match $crate::scalar::vector_unit() {
                    // SAFETY: `vector_unit` names a unit only when the CPU has it.
                    $crate::scalar::VectorUnit::Avx512 => return unsafe { avx512($($arg),*) },
                    // SAFETY: as above.
                    $crate::scalar::VectorUnit::Avx2 => return unsafe { avx2($($arg),*) },
                    $crate::scalar::VectorUnit::Baseline => {}
                }
            }
            $inner($($arg),*)
        }
    };
}
pub(crate) use widest_fn;

/// Defines `$name`, which runs `$inner` (an `#[inline(always)]` method or
/// function with the same arguments) compiled for the widest vector unit the
/// CPU has: AVX-512 or AVX2 when present (checked once, [`vector_unit`]),
/// else the baseline. The engine's cycle loops (a group over every φ, a
/// thread piece over every φ) run this way, so loops without branches
/// (offsets, straight thread pieces, square roots) process 4 or 8 positions
/// per instruction. Plain IEEE arithmetic gives the same bits at any width
/// (no fused multiply-add is formed), so results do not depend on the
/// machine.
macro_rules! widest {
    ($(#[$meta:meta])* $vis:vis fn $name:ident(&self $(, $arg:ident: $ty:ty)*) -> $ret:ty
        => $inner:ident for $this:ty $(, <$g:ident: $bound:path>)?) => {
        $(#[$meta])*
        $vis fn $name(&self $(, $arg: $ty)*) -> $ret {
            $crate::scalar::widest_fn! {
                fn run<$($g: $bound)?>(this: &$this $(, $arg: $ty)*) -> $ret => <$this>::$inner
            }
            run(self $(, $arg)*)
        }
    };
}
pub(crate) use widest;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrt_slice_equals_sqrt_for_every_length() {
        for n in 0..40 {
            let x: Vec<f64> = (0..n).map(|k| (k * k) as f64 * 0.37 + 1e-3).collect();
            let mut y = x.clone();
            f64::sqrt_slice(&mut y);
            assert!(x.iter().zip(&y).all(|(a, b)| a.sqrt() == *b), "n = {n}");
            let mut d: Vec<Dual2_64> = x.iter().map(|&v| Dual2_64::new(v, 1.0, 0.0)).collect();
            Dual2_64::sqrt_slice(&mut d);
            assert!(
                x.iter()
                    .zip(&d)
                    .all(|(a, b)| a.sqrt() == b.re && (b.v1 - 0.5 / a.sqrt()).abs() < 1e-12)
            );
        }
    }
    use nalgebra::ComplexField;

    #[test]
    fn angle_of_has_finite_derivatives_on_the_axes() {
        // (x, y) = (cos t, sin t) at t = 90°: x is exactly 0 in the value.
        let t = Dual2_64::new(std::f64::consts::FRAC_PI_2, 1.0, 0.0);
        let (y, x) = (t.sin(), Dual2_64::new(0.0, -1.0, 0.0));
        let a = y.angle_of(x);
        assert!((a.re - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((a.v1 - 1.0).abs() < 1e-12 && a.v2.abs() < 1e-12, "{a:?}");
        for k in 0..16 {
            let t = Dual2_64::new(k as f64 * 0.4 - 3.0, 1.0, 0.0);
            let a = t.sin().times(2.0).angle_of(t.cos().times(2.0));
            let want = (t.re + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
            assert!((a.re - want).abs() < 1e-12 && (a.v1 - 1.0).abs() < 1e-12 && a.v2.abs() < 1e-12);
        }
        assert_eq!(3.0f64.angle_of(4.0), 3.0f64.atan2(4.0));
    }
}
