//! Points, vectors and fixed coordinate frames.

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::scalar::Real;

pub type V2<T> = Vector2<T>;
pub type V3<T> = Vector3<T>;

/// `v` turned by +90° in its plane: (x, y) → (−y, x).
#[inline(always)]
pub fn perp<T: Real>(v: V2<T>) -> V2<T> {
    V2::new(-v.y, v.x)
}

/// z-component of the planar cross product `a × b`.
#[inline(always)]
pub fn cross2<T: Real>(a: V2<T>, b: V2<T>) -> T {
    a.x * b.y - a.y * b.x
}

/// `|v|`, with zero derivatives where `v = 0` (the norm has a corner there;
/// the plain dual-number square root would give NaN).
#[inline]
pub fn norm_or_zero<T: Real>(v: V3<T>) -> T {
    let n2 = v.norm_squared();
    if n2.re() > 0.0 { n2.sqrt() } else { T::zero() }
}

/// A rigid placement: `p_world = origin + rot · p_local`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement<T: Real> {
    pub rot: Matrix3<T>,
    pub origin: V3<T>,
}

impl<T: Real> Placement<T> {
    pub fn identity() -> Self {
        Placement {
            rot: Matrix3::identity(),
            origin: V3::zeros(),
        }
    }

    /// Local coordinates → world.
    #[inline]
    pub fn to_world(&self, p: V3<T>) -> V3<T> {
        self.origin + self.rot * p
    }

    /// A local direction → world.
    #[inline]
    pub fn dir_to_world(&self, d: V3<T>) -> V3<T> {
        self.rot * d
    }

    /// World coordinates → local.
    #[inline]
    pub fn to_local(&self, p: V3<T>) -> V3<T> {
        self.rot.tr_mul(&(p - self.origin))
    }

    /// `self` placed inside `parent`: `parent ∘ self`.
    pub fn within(&self, parent: &Placement<T>) -> Self {
        Placement {
            rot: parent.rot * self.rot,
            origin: parent.to_world(self.origin),
        }
    }

    /// The frame's xy-plane as a plane of motion, `None` for the world's own
    /// (the fast path every planar group takes by default).
    pub fn is_identity(&self) -> bool {
        self.rot == Matrix3::identity() && self.origin == V3::zeros()
    }
}

/// Rotation by `angle_rad` about the coordinate axis `axis` (0 = x, 1 = y, 2 = z).
pub fn axis_rotation<T: Real>(axis: usize, angle_rad: T) -> Matrix3<T> {
    let (s, c) = angle_rad.sin_cos();
    let (o, z) = (T::one(), T::zero());
    match axis {
        0 => Matrix3::new(o, z, z, z, c, -s, z, s, c),
        1 => Matrix3::new(c, z, s, z, o, z, -s, z, c),
        _ => Matrix3::new(c, -s, z, s, c, z, z, z, o),
    }
}

/// A plane of motion for planar groups: the xy-plane of a frame.
/// `None` is the world xy-plane, handled without any transformation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane<T: Real>(pub Option<Placement<T>>);

impl<T: Real> Plane<T> {
    pub const WORLD: Plane<T> = Plane(None);

    /// In-plane coordinates of a world point (its projection on the plane).
    #[inline(always)]
    pub fn project(&self, p: &V3<T>) -> V2<T> {
        match &self.0 {
            None => V2::new(p.x, p.y),
            Some(f) => f.to_local(*p).xy(),
        }
    }

    /// World point of in-plane coordinates `q` at height `lift` above the plane.
    #[inline(always)]
    pub fn lift(&self, q: V2<T>, lift: T) -> V3<T> {
        match &self.0 {
            None => V3::new(q.x, q.y, lift),
            Some(f) => f.to_world(V3::new(q.x, q.y, lift)),
        }
    }

    /// World direction of an in-plane direction.
    #[inline(always)]
    pub fn dir(&self, q: V2<T>) -> V3<T> {
        match &self.0 {
            None => V3::new(q.x, q.y, T::zero()),
            Some(f) => f.dir_to_world(V3::new(q.x, q.y, T::zero())),
        }
    }
}

/// Projection onto a plane of motion and back, chosen once per group so the
/// per-φ loops carry no branch for it (see [`with_plane!`](crate::with_plane)).
pub trait PlaneMap<T: Real>: Copy {
    fn project(&self, p: &V3<T>) -> V2<T>;
    fn lift(&self, q: V2<T>, lift: T) -> V3<T>;
    /// In-plane components of a direction (a velocity, an acceleration).
    fn project_dir(&self, d: &V3<T>) -> V2<T>;
    /// World direction of an in-plane direction.
    fn lift_dir(&self, q: V2<T>) -> V3<T>;
}

/// The world xy-plane: projection drops z.
#[derive(Clone, Copy)]
pub struct WorldXy;

impl<T: Real> PlaneMap<T> for WorldXy {
    #[inline(always)]
    fn project(&self, p: &V3<T>) -> V2<T> {
        V2::new(p.x, p.y)
    }
    #[inline(always)]
    fn lift(&self, q: V2<T>, lift: T) -> V3<T> {
        V3::new(q.x, q.y, lift)
    }
    #[inline(always)]
    fn project_dir(&self, d: &V3<T>) -> V2<T> {
        V2::new(d.x, d.y)
    }
    #[inline(always)]
    fn lift_dir(&self, q: V2<T>) -> V3<T> {
        V3::new(q.x, q.y, T::zero())
    }
}

/// The xy-plane of a frame.
#[derive(Clone, Copy)]
pub struct FrameXy<'a, T: Real>(pub &'a Placement<T>);

impl<T: Real> PlaneMap<T> for FrameXy<'_, T> {
    #[inline(always)]
    fn project(&self, p: &V3<T>) -> V2<T> {
        self.0.to_local(*p).xy()
    }
    #[inline(always)]
    fn lift(&self, q: V2<T>, lift: T) -> V3<T> {
        self.0.to_world(V3::new(q.x, q.y, lift))
    }
    #[inline(always)]
    fn project_dir(&self, d: &V3<T>) -> V2<T> {
        self.0.rot.tr_mul(d).xy()
    }
    #[inline(always)]
    fn lift_dir(&self, q: V2<T>) -> V3<T> {
        self.0.dir_to_world(V3::new(q.x, q.y, T::zero()))
    }
}

/// Evaluates `$body` with `$pl` bound to the [`PlaneMap`] of `$plane`
/// (a [`Plane`]): the world-or-frame choice is made once, outside the loops
/// in `$body`.
#[macro_export]
macro_rules! with_plane {
    ($plane:expr, $pl:ident => $body:expr) => {
        match &($plane).0 {
            None => {
                let $pl = $crate::geometry::WorldXy;
                $body
            }
            Some(f) => {
                let $pl = $crate::geometry::FrameXy(f);
                $body
            }
        }
    };
}

/// The convex hull of planar points, counter-clockwise without repeated or
/// collinear vertices (Andrew's monotone chain); sorts `points`.
pub fn convex_hull(points: &mut [[f64; 2]]) -> Vec<[f64; 2]> {
    points.sort_by(by_x_then_y);
    convex_hull_sorted(points)
}

/// The order [`convex_hull`] sorts planar points in: by x, then by y.
pub fn by_x_then_y(a: &[f64; 2], b: &[f64; 2]) -> std::cmp::Ordering {
    a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1]))
}

/// [`convex_hull`] of points already in [`by_x_then_y`] order.
pub fn convex_hull_sorted(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    debug_assert!(points.is_sorted_by(|a, b| by_x_then_y(a, b).is_le()));
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(points.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in ordered {
            while hull.len() >= start + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// (a − o) × (b − o): positive when o → a → b turns counter-clockwise.
pub fn turn(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// How far `phi_deg` lies after `phi0_deg` in the cycle, [0, 360) deg:
/// `(phi_deg − phi0_deg).rem_euclid(360)`, bit for bit, without its
/// division where the two are less than two turns apart (a cycle's grid
/// against an angle of the cycle given in either turn).
#[inline]
pub fn since_deg(phi_deg: f64, phi0_deg: f64) -> f64 {
    let d = phi_deg - phi0_deg;
    if d.abs() < 360.0 {
        // fmod(d, 360) is d itself here.
        if d < 0.0 { d + 360.0 } else { d }
    } else if (360.0..720.0).contains(&d) {
        // fmod(d, 360) is d − 360, exact (Sterbenz).
        d - 360.0
    } else if d > -720.0 && d < -360.0 {
        // fmod(d, 360) is d + 360 < 0, exact; rem_euclid adds a turn.
        (d + 360.0) + 360.0
    } else {
        d.rem_euclid(360.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn since_is_the_euclidean_remainder_bit_for_bit() {
        let mut x = 0.123_456_789f64;
        for _ in 0..20_000 {
            // A scrambled walk over ±900° with exact ties at the turn.
            x = (x * 7919.0 + 0.618_033_988_7).fract();
            for (phi, phi0) in [
                (x * 1800.0 - 900.0, 37.5),
                (x * 720.0, 359.0),
                (x * 2880.0 - 1440.0, -0.25),
                (360.0, 0.0),
                (720.0, 0.0),
                (-360.0, 0.0),
                (-720.0, 0.0),
                (-0.0, 0.0),
                (0.0, 360.0),
            ] {
                let (a, b) = (since_deg(phi, phi0), (phi - phi0).rem_euclid(360.0));
                assert_eq!(a.to_bits(), b.to_bits(), "φ = {phi}, φ0 = {phi0}");
            }
        }
    }

    #[test]
    fn hull_of_a_square_with_inner_and_edge_points() {
        let mut pts = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0]];
        assert_eq!(
            convex_hull(&mut pts),
            vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
        );
        assert!(turn([0.0, 0.0], [1.0, 0.0], [1.0, 1.0]) > 0.0);
    }
    use approx::assert_relative_eq;

    #[test]
    fn rotations_are_right_handed() {
        let q = std::f64::consts::FRAC_PI_2;
        let r = axis_rotation(2, q) * V3::new(1.0, 0.0, 0.0);
        assert_relative_eq!(r, V3::new(0.0, 1.0, 0.0), epsilon = 1e-15);
        let r = axis_rotation(0, q) * V3::new(0.0, 1.0, 0.0);
        assert_relative_eq!(r, V3::new(0.0, 0.0, 1.0), epsilon = 1e-15);
        let r = axis_rotation(1, q) * V3::new(0.0, 0.0, 1.0);
        assert_relative_eq!(r, V3::new(1.0, 0.0, 0.0), epsilon = 1e-15);
    }

    #[test]
    fn placement_round_trip() {
        let f = Placement {
            rot: axis_rotation(0, 0.3) * axis_rotation(2, 1.1),
            origin: V3::new(1.0, -2.0, 3.0),
        };
        let p = V3::new(0.5, 7.0, -1.0);
        assert_relative_eq!(f.to_local(f.to_world(p)), p, epsilon = 1e-12);
        let plane = Plane(Some(f));
        let q = plane.project(&plane.lift(V2::new(2.0, 3.0), 4.0));
        assert_relative_eq!(q, V2::new(2.0, 3.0), epsilon = 1e-12);
    }
}
