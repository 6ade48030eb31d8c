//! Path geometry of one profile (pick_and_place.md §7.2 – §7.6): the polyline S → IP1 → IP2 → T,
//! the half ellipse, the Bézier blends, the park-position shape, arc-length parametrisation,
//! the stop points of the rest-to-rest sub-profiles and the orientation/coupling windows.
//!
//! Everything is planned in a fixed planning snapshot (§15.1); belt motion is superposed later.

use nalgebra::Vector3;
use std::f64::consts::PI;

/// A point or direction in MCS [units].
pub type Vec3 = Vector3<f64>;

/// Lengths below this are treated as zero (dropped segments, coincident points) [units].
pub const LENGTH_EPS: f64 = 1e-9;
/// Below this half-axis the ellipse degenerates and the profile is planned linear (§7.4) [units].
pub const ELLIPSE_MIN_HALF_AXIS: f64 = 0.001;
/// Intervals of the arc-length tables of curved segments.
const TABLE_INTERVALS: usize = 128;

// 5-point Gauss–Legendre on [-1, 1].
const GL_X: [f64; 5] = [
    0.0,
    -0.538_469_310_105_683_1,
    0.538_469_310_105_683_1,
    -0.906_179_845_938_664,
    0.906_179_845_938_664,
];
const GL_W: [f64; 5] = [
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
    0.236_926_885_056_189_1,
];

/// A curve given by a parameter u ∈ [0, u_max] whose arc length is tabulated.
#[derive(Clone, Debug)]
enum Curve {
    /// Quadratic Bézier B0, B1, B2, u ∈ [0, 1] (§7.5).
    Bezier { b0: Vec3, b1: Vec3, b2: Vec3 },
    /// Half ellipse E(φ) = C − a·cos φ·h + b·sin φ·e_z, φ ∈ [0, π] (§7.4).
    HalfEllipse { c: Vec3, h: Vec3, a: f64, b: f64 },
}

impl Curve {
    fn u_max(&self) -> f64 {
        match self {
            Curve::Bezier { .. } => 1.0,
            Curve::HalfEllipse { .. } => PI,
        }
    }
    fn point(&self, u: f64) -> Vec3 {
        match self {
            Curve::Bezier { b0, b1, b2 } => {
                b0 * (1.0 - u) * (1.0 - u) + b1 * (2.0 * u * (1.0 - u)) + b2 * (u * u)
            }
            Curve::HalfEllipse { c, h, a, b } => c - h * (a * u.cos()) + Vec3::z() * (b * u.sin()),
        }
    }
    fn derivative(&self, u: f64) -> Vec3 {
        match self {
            Curve::Bezier { b0, b1, b2 } => (b1 - b0) * (2.0 * (1.0 - u)) + (b2 - b1) * (2.0 * u),
            Curve::HalfEllipse { h, a, b, .. } => h * (a * u.sin()) + Vec3::z() * (b * u.cos()),
        }
    }
    fn speed(&self, u: f64) -> f64 {
        self.derivative(u).norm()
    }
    fn integrate(&self, u0: f64, u1: f64) -> f64 {
        let (m, r) = (0.5 * (u0 + u1), 0.5 * (u1 - u0));
        (0..5)
            .map(|i| GL_W[i] * self.speed(m + r * GL_X[i]))
            .sum::<f64>()
            * r
    }
}

/// A curved segment with its arc-length table (cumulative length at uniform parameter steps).
#[derive(Clone, Debug)]
struct Tabulated {
    curve: Curve,
    cumulative: Vec<f64>,
}

impl Tabulated {
    fn new(curve: Curve) -> Self {
        let du = curve.u_max() / TABLE_INTERVALS as f64;
        let mut cumulative = Vec::with_capacity(TABLE_INTERVALS + 1);
        let mut acc = 0.0;
        cumulative.push(0.0);
        for i in 0..TABLE_INTERVALS {
            acc += curve.integrate(i as f64 * du, (i + 1) as f64 * du);
            cumulative.push(acc);
        }
        Tabulated { curve, cumulative }
    }
    fn length(&self) -> f64 {
        self.cumulative[TABLE_INTERVALS]
    }
    /// Parameter at arc length s (Newton within the table interval).
    fn param(&self, s: f64) -> f64 {
        let s = s.clamp(0.0, self.length());
        let du = self.curve.u_max() / TABLE_INTERVALS as f64;
        let i = match self.cumulative.binary_search_by(|c| c.total_cmp(&s)) {
            Ok(i) => return i as f64 * du,
            Err(i) => i.saturating_sub(1).min(TABLE_INTERVALS - 1),
        };
        let u0 = i as f64 * du;
        let (s0, s1) = (self.cumulative[i], self.cumulative[i + 1]);
        let mut u = u0 + du * (s - s0) / (s1 - s0).max(1e-300);
        for _ in 0..4 {
            let f = s0 + self.curve.integrate(u0, u) - s;
            let sp = self.curve.speed(u);
            if sp <= 1e-12 {
                break;
            }
            u = (u - f / sp).clamp(u0, u0 + du);
        }
        u
    }
}

/// One piece of the geometric path.
#[derive(Clone, Debug)]
enum Piece {
    Line { p0: Vec3, u: Vec3 },
    Curve(Tabulated),
}

#[derive(Clone, Debug)]
struct Segment {
    start: f64,
    length: f64,
    piece: Piece,
}

impl Segment {
    fn point(&self, s: f64) -> Vec3 {
        match &self.piece {
            Piece::Line { p0, u } => p0 + u * s,
            Piece::Curve(t) => t.curve.point(t.param(s)),
        }
    }
    fn tangent(&self, s: f64) -> Vec3 {
        match &self.piece {
            Piece::Line { u, .. } => *u,
            Piece::Curve(t) => {
                let d = t.curve.derivative(t.param(s));
                let n = d.norm();
                if n > 0.0 {
                    d / n
                } else {
                    Vec3::zeros()
                }
            }
        }
    }
}

/// The geometry of one profile, parametrised by arc length σ ∈ [0, length].
#[derive(Clone, Debug)]
pub struct PathGeometry {
    segments: Vec<Segment>,
    /// Total arc length [units].
    pub length: f64,
    /// Arc positions where the path velocity is 0: ends of the rest-to-rest sub-profiles,
    /// ascending, the last one is `length` (§7.3, §7.4).
    pub stops: Vec<f64>,
    /// Arc positions at which IP1, IP2 and T count as passed (`iProfilePointPassed`, §7.10).
    pub point_arcs: [f64; 3],
    /// Orientation/Aux1 window [σ0, σ1] (§7.3 – §7.6).
    pub orientation_window: (f64, f64),
    /// Coupling window [σ0, σ1] (§15.2).
    pub coupling_window: (f64, f64),
    /// The ellipse could not be built and the profile is linear (warning 90007).
    pub fallback_linear: bool,
}

impl PathGeometry {
    fn segment_at(&self, s: f64) -> &Segment {
        let i = self
            .segments
            .partition_point(|g| g.start <= s)
            .saturating_sub(1);
        &self.segments[i]
    }

    /// TCP position at arc length σ (clamped) in the planning snapshot.
    pub fn position(&self, s: f64) -> Vec3 {
        let s = s.clamp(0.0, self.length);
        let g = self.segment_at(s);
        g.point((s - g.start).min(g.length))
    }

    /// Unit tangent at σ.
    pub fn tangent(&self, s: f64) -> Vec3 {
        let s = s.clamp(0.0, self.length);
        let g = self.segment_at(s);
        g.tangent((s - g.start).min(g.length))
    }

    /// Largest |dq/dσ| of X, Y, Z over [σ0, σ1] (§7.8); curved pieces are sampled.
    pub fn max_tangent_components(&self, s0: f64, s1: f64) -> [f64; 3] {
        let mut c = [0.0f64; 3];
        let mut take = |t: Vec3| {
            for q in 0..3 {
                c[q] = c[q].max(t[q].abs());
            }
        };
        for g in &self.segments {
            let (a, b) = (g.start.max(s0), (g.start + g.length).min(s1));
            if b < a {
                continue;
            }
            match &g.piece {
                Piece::Line { u, .. } => take(*u),
                Piece::Curve(_) => {
                    const N: usize = 64;
                    for i in 0..=N {
                        let s = a + (b - a) * i as f64 / N as f64;
                        take(g.tangent(s - g.start));
                    }
                }
            }
        }
        c
    }

    /// Window factor u ∈ [0, 1] of σ in a window (0 before, 1 after).
    pub fn window_fraction(window: (f64, f64), s: f64) -> f64 {
        let (w0, w1) = window;
        if s <= w0 {
            0.0
        } else if s >= w1 || w1 - w0 <= LENGTH_EPS {
            1.0
        } else {
            (s - w0) / (w1 - w0)
        }
    }

    /// Coupling factor k(σ) = 10u³ − 15u⁴ + 6u⁵ (§15.1).
    pub fn coupling(&self, s: f64) -> f64 {
        let u = Self::window_fraction(self.coupling_window, s);
        u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
    }

    /// dk/dσ at σ.
    pub fn coupling_slope(&self, s: f64) -> f64 {
        let (w0, w1) = self.coupling_window;
        if s <= w0 || s >= w1 || w1 - w0 <= LENGTH_EPS {
            return 0.0;
        }
        let u = (s - w0) / (w1 - w0);
        30.0 * u * u * (1.0 - u) * (1.0 - u) / (w1 - w0)
    }
}

/// Accumulates pieces into a [`PathGeometry`].
struct Builder {
    segments: Vec<Segment>,
    length: f64,
}

impl Builder {
    fn new() -> Self {
        Builder {
            segments: Vec::new(),
            length: 0.0,
        }
    }
    fn line(&mut self, p0: Vec3, p1: Vec3) {
        let d = p1 - p0;
        let len = d.norm();
        if len <= LENGTH_EPS {
            return;
        }
        self.segments.push(Segment {
            start: self.length,
            length: len,
            piece: Piece::Line { p0, u: d / len },
        });
        self.length += len;
    }
    fn curve(&mut self, c: Curve) {
        let t = Tabulated::new(c);
        let len = t.length();
        if len <= LENGTH_EPS {
            return;
        }
        self.segments.push(Segment {
            start: self.length,
            length: len,
            piece: Piece::Curve(t),
        });
        self.length += len;
    }
    fn finish(mut self, at: Vec3) -> Vec<Segment> {
        if self.segments.is_empty() {
            // A zero-length path still answers position queries.
            self.segments.push(Segment {
                start: 0.0,
                length: 0.0,
                piece: Piece::Line {
                    p0: at,
                    u: Vec3::zeros(),
                },
            });
        }
        self.segments
    }
}

/// The four characteristic points of a pick & place profile in the planning snapshot (§7.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfilePoints {
    /// Start S.
    pub s: Vec3,
    /// Intermediate point 1 (≡ S when its height is 0).
    pub ip1: Vec3,
    /// Intermediate point 2 (≡ T when its height is 0).
    pub ip2: Vec3,
    /// Target T.
    pub t: Vec3,
}

/// Shape of a pick & place profile (§7.3 – §7.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeParams {
    /// `ePathMode` = Elliptical.
    pub elliptical: bool,
    /// `lrBlendingRadius` r [units].
    pub blending_radius: f64,
    /// `lrZDistElliptical` b [units].
    pub z_dist_elliptical: f64,
}

fn dist(a: Vec3, b: Vec3) -> f64 {
    (b - a).norm()
}

fn unit(a: Vec3, b: Vec3) -> Vec3 {
    let d = b - a;
    let n = d.norm();
    if n > 0.0 {
        d / n
    } else {
        Vec3::zeros()
    }
}

/// The δ of §7.5 for a window end whose height is 0 (r > 0: δ = r; r = 0: only the coupling
/// window moves, by `coupling_delta`).
fn windows(
    w0: f64,
    w1: f64,
    ip1_is_s: bool,
    ip2_is_t: bool,
    r: f64,
    coupling_delta: f64,
) -> ((f64, f64), (f64, f64)) {
    let mut o = (w0, w1);
    let mut c = (w0, w1);
    let len = (w1 - w0).max(0.0);
    if r > 0.0 {
        let d = r.min(0.5 * len);
        if ip1_is_s {
            o.0 = w0 + d;
        }
        if ip2_is_t {
            o.1 = w1 - d;
        }
        c = o;
    } else {
        let d = coupling_delta.min(0.5 * len);
        if ip1_is_s {
            c.0 = w0 + d;
        }
        if ip2_is_t {
            c.1 = w1 - d;
        }
    }
    (o, c)
}

/// Plans the geometry of a pick & place profile (§7.3 – §7.5).
pub fn pick_place(p: &ProfilePoints, shape: &ShapeParams) -> PathGeometry {
    if shape.elliptical {
        if let Some(g) = ellipse(p, shape) {
            return g;
        }
        let mut g = linear(p, shape.blending_radius);
        g.fallback_linear = true;
        return g;
    }
    linear(p, shape.blending_radius)
}

/// Linear profile with or without blends (§7.3, §7.5).
fn linear(p: &ProfilePoints, r: f64) -> PathGeometry {
    let (l1, l2, l3) = (dist(p.s, p.ip1), dist(p.ip1, p.ip2), dist(p.ip2, p.t));
    let ip1_is_s = l1 <= LENGTH_EPS;
    let ip2_is_t = l3 <= LENGTH_EPS;
    let mut b = Builder::new();
    let mut stops = Vec::new();
    let point_arcs;
    let (w0, w1);
    if r <= 0.0 {
        b.line(p.s, p.ip1);
        let a1 = b.length;
        b.line(p.ip1, p.ip2);
        let a2 = b.length;
        b.line(p.ip2, p.t);
        for a in [a1, a2] {
            if a > LENGTH_EPS && a < b.length - LENGTH_EPS && !stops.contains(&a) {
                stops.push(a);
            }
        }
        point_arcs = [a1, a2, b.length];
        (w0, w1) = (a1, a2);
    } else {
        // Blend radii limited by half of each neighbouring segment (§7.5).
        let r1 = if ip1_is_s || l2 <= LENGTH_EPS {
            0.0
        } else {
            r.min(0.5 * l1).min(0.5 * l2)
        };
        let r2 = if ip2_is_t || l2 <= LENGTH_EPS {
            0.0
        } else {
            r.min(0.5 * l2).min(0.5 * l3)
        };
        let (u1, u2, u3) = (unit(p.s, p.ip1), unit(p.ip1, p.ip2), unit(p.ip2, p.t));
        let mut cursor = p.s;
        let (mut m1, mut m2);
        let (mut ws, mut we);
        if r1 > 0.0 {
            let b0 = p.ip1 - u1 * r1;
            b.line(cursor, b0);
            ws = b.length;
            b.curve(Curve::Bezier {
                b0,
                b1: p.ip1,
                b2: p.ip1 + u2 * r1,
            });
            m1 = 0.5 * (ws + b.length);
            cursor = p.ip1 + u2 * r1;
        } else {
            b.line(cursor, p.ip1);
            ws = b.length;
            m1 = b.length;
            cursor = p.ip1;
        }
        if r2 > 0.0 {
            let b0 = p.ip2 - u2 * r2;
            b.line(cursor, b0);
            let st = b.length;
            b.curve(Curve::Bezier {
                b0,
                b1: p.ip2,
                b2: p.ip2 + u3 * r2,
            });
            m2 = 0.5 * (st + b.length);
            we = b.length;
            cursor = p.ip2 + u3 * r2;
        } else {
            b.line(cursor, p.ip2);
            m2 = b.length;
            we = b.length;
            cursor = p.ip2;
        }
        b.line(cursor, p.t);
        if ip1_is_s {
            (ws, m1) = (0.0, 0.0);
        }
        if ip2_is_t {
            (we, m2) = (b.length, b.length);
        }
        point_arcs = [m1, m2, b.length];
        (w0, w1) = (ws, we);
    }
    let length = b.length;
    stops.push(length);
    let (orientation_window, coupling_window) =
        windows(w0, w1, ip1_is_s, ip2_is_t, r, 0.1 * (w1 - w0));
    PathGeometry {
        segments: b.finish(p.s),
        length,
        stops,
        point_arcs,
        orientation_window,
        coupling_window,
        fallback_linear: false,
    }
}

/// Ellipse profile (§7.4); `None` when the ellipse degenerates (a < 0.001).
fn ellipse(p: &ProfilePoints, shape: &ShapeParams) -> Option<PathGeometry> {
    let (e1, e2) = if p.ip1.z < p.ip2.z {
        (Vec3::new(p.ip1.x, p.ip1.y, p.ip2.z), p.ip2)
    } else {
        (p.ip1, Vec3::new(p.ip2.x, p.ip2.y, p.ip1.z))
    };
    let a = 0.5 * dist(e1, e2);
    if a < ELLIPSE_MIN_HALF_AXIS {
        return None;
    }
    let h = (e2 - e1) / (2.0 * a);
    let c = 0.5 * (e1 + e2);
    let bz = shape.z_dist_elliptical;
    let mut b = Builder::new();
    b.line(p.s, p.ip1);
    let a1 = b.length;
    b.line(p.ip1, e1);
    b.curve(Curve::HalfEllipse { c, h, a, b: bz });
    b.line(e2, p.ip2);
    let a2 = b.length;
    b.line(p.ip2, p.t);
    let length = b.length;
    let (l1, l3) = (a1, length - a2);
    let l_mid = a2 - a1;
    let ip1_is_s = l1 <= LENGTH_EPS;
    let ip2_is_t = l3 <= LENGTH_EPS;
    let r = shape.blending_radius;
    let mut stops = Vec::new();
    let (w0, w1);
    if r <= 0.0 {
        for x in [a1, a2] {
            if x > LENGTH_EPS && x < length - LENGTH_EPS && !stops.contains(&x) {
                stops.push(x);
            }
        }
        (w0, w1) = (a1, a2);
    } else {
        // The geometry is already tangent-continuous: r only removes the stops and moves the
        // windows by r_eff (§7.5).
        let r1 = if ip1_is_s {
            0.0
        } else {
            r.min(0.5 * l1).min(0.5 * l_mid)
        };
        let r2 = if ip2_is_t {
            0.0
        } else {
            r.min(0.5 * l_mid).min(0.5 * l3)
        };
        (w0, w1) = (a1 - r1, a2 + r2);
    }
    stops.push(length);
    let coupling_delta = (0.1 * (w1 - w0)).min(0.5 * bz);
    let (orientation_window, coupling_window) =
        windows(w0, w1, ip1_is_s, ip2_is_t, r, coupling_delta);
    Some(PathGeometry {
        segments: b.finish(p.s),
        length,
        stops,
        point_arcs: [a1, a2, length],
        orientation_window,
        coupling_window,
        fallback_linear: false,
    })
}

/// A straight move from `from` to the start of `rest`, followed by `rest` (§9.2: resume after
/// jogging away from the hold point). The TCP stops at the junction; `passed` profile points
/// (0 … 2) count as passed from the start.
pub fn prepend_line(from: Vec3, rest: &PathGeometry, passed: usize) -> PathGeometry {
    let to = rest.position(0.0);
    let l0 = dist(from, to);
    let mut segments = Vec::with_capacity(rest.segments.len() + 1);
    if l0 > LENGTH_EPS {
        segments.push(Segment {
            start: 0.0,
            length: l0,
            piece: Piece::Line {
                p0: from,
                u: (to - from) / l0,
            },
        });
    } else if rest.length <= LENGTH_EPS {
        segments.push(Segment {
            start: 0.0,
            length: 0.0,
            piece: Piece::Line {
                p0: from,
                u: Vec3::zeros(),
            },
        });
    }
    let l0 = if l0 > LENGTH_EPS { l0 } else { 0.0 };
    for g in &rest.segments {
        if g.length > 0.0 {
            segments.push(Segment {
                start: g.start + l0,
                ..g.clone()
            });
        }
    }
    let mut stops = Vec::with_capacity(rest.stops.len() + 1);
    if l0 > 0.0 && rest.length > LENGTH_EPS {
        stops.push(l0);
    }
    stops.extend(rest.stops.iter().map(|s| s + l0));
    let mut point_arcs = rest.point_arcs.map(|a| a + l0);
    for a in point_arcs.iter_mut().take(passed) {
        *a = 0.0;
    }
    let shift = |w: (f64, f64)| (w.0 + l0, w.1 + l0);
    // After IP1 the orientation and coupling complete on the straight move.
    let (orientation_window, coupling_window) = if passed == 0 {
        (shift(rest.orientation_window), shift(rest.coupling_window))
    } else {
        ((0.0, l0), (0.0, l0))
    };
    PathGeometry {
        segments,
        length: l0 + rest.length,
        stops,
        point_arcs,
        orientation_window,
        coupling_window,
        fallback_linear: false,
    }
}

/// Which end of a park path is on a belt (§7.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParkDirection {
    /// From a belt or a static position to the park pose: windows from the blend start at IPp
    /// to the park pose.
    ToPark,
    /// From the park pose onto a belt: windows from the park pose to the blend end at IPp.
    FromPark,
}

/// The two-segment park path S → IPp → T with a blend of `radius` at IPp (§7.6).
pub fn park_path(s: Vec3, ipp: Vec3, t: Vec3, radius: f64, dir: ParkDirection) -> PathGeometry {
    let (l1, l2) = (dist(s, ipp), dist(ipp, t));
    let r = radius.min(0.5 * l1).min(0.5 * l2).max(0.0);
    let mut b = Builder::new();
    let mut stops = Vec::new();
    let (bs, be, mid);
    if r > LENGTH_EPS {
        let (u1, u2) = (unit(s, ipp), unit(ipp, t));
        b.line(s, ipp - u1 * r);
        bs = b.length;
        b.curve(Curve::Bezier {
            b0: ipp - u1 * r,
            b1: ipp,
            b2: ipp + u2 * r,
        });
        be = b.length;
        mid = 0.5 * (bs + be);
        b.line(ipp + u2 * r, t);
    } else {
        b.line(s, ipp);
        bs = b.length;
        be = b.length;
        mid = b.length;
        if bs > LENGTH_EPS && l2 > LENGTH_EPS {
            stops.push(bs);
        }
        b.line(ipp, t);
    }
    let length = b.length;
    stops.push(length);
    let w = match dir {
        ParkDirection::ToPark => (bs, length),
        ParkDirection::FromPark => (0.0, be),
    };
    PathGeometry {
        segments: b.finish(s),
        length,
        stops,
        point_arcs: [mid, mid, length],
        orientation_window: w,
        coupling_window: w,
        fallback_linear: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn bezier_closest_approach_is_midpoint_formula() {
        // 90° corner: d_min = 0.3536·r (§7.5).
        let p = ProfilePoints {
            s: v(0., 0., 0.),
            ip1: v(0., 0., 50.),
            ip2: v(100., 0., 50.),
            t: v(100., 0., 0.),
        };
        let g = pick_place(
            &p,
            &ShapeParams {
                elliptical: false,
                blending_radius: 10.0,
                z_dist_elliptical: 0.0,
            },
        );
        let d = (0..=10000)
            .map(|i| (g.position(g.length * i as f64 / 10000.0) - p.ip1).norm())
            .fold(f64::INFINITY, f64::min);
        assert!((d - 0.353_553_4 * 10.0).abs() < 1e-3, "{d}");
    }

    #[test]
    fn w2_blend_lengths_and_windows() {
        // §19 W2: r_eff 20 and 15, Bézier lengths 29.389 / 26.388, total 277.673, windows 30 …
        // 262.673, stops none.
        let p = ProfilePoints {
            s: v(0., 0., 100.),
            ip1: v(0., 0., 150.),
            ip2: v(200., 0., 80.),
            t: v(200., 0., 50.),
        };
        let g = pick_place(
            &p,
            &ShapeParams {
                elliptical: false,
                blending_radius: 20.0,
                z_dist_elliptical: 0.0,
            },
        );
        assert!((g.length - 277.673).abs() < 1e-3, "{}", g.length);
        assert_eq!(g.stops, vec![g.length]);
        let bez: Vec<f64> = g
            .segments
            .iter()
            .filter(|s| matches!(s.piece, Piece::Curve(_)))
            .map(|s| s.length)
            .collect();
        assert!(
            (bez[0] - 29.389).abs() < 1e-3 && (bez[1] - 26.388).abs() < 1e-3,
            "{bez:?}"
        );
        assert!((g.orientation_window.0 - 30.0).abs() < 1e-9);
        assert!((g.orientation_window.1 - 262.673).abs() < 1e-3);
        assert_eq!(g.coupling_window, g.orientation_window);
    }

    #[test]
    fn w3_ellipse_arc_and_stops() {
        // §19 W3: compensation 60, half-ellipse arc 345.197, sub-profiles 20 / 405.197 / 40.
        let p = ProfilePoints {
            s: v(0., 0., 100.),
            ip1: v(0., 0., 120.),
            ip2: v(300., 0., 180.),
            t: v(300., 0., 140.),
        };
        let g = pick_place(
            &p,
            &ShapeParams {
                elliptical: true,
                blending_radius: 0.0,
                z_dist_elliptical: 60.0,
            },
        );
        assert!((g.length - 465.197).abs() < 1e-3, "{}", g.length);
        assert!(
            (g.stops[0] - 20.0).abs() < 1e-9 && (g.stops[1] - 425.197).abs() < 1e-3,
            "{:?}",
            g.stops
        );
        let apex = g.position(20.0 + 60.0 + 345.197 / 2.0);
        assert!((apex - v(150., 0., 240.)).norm() < 1e-3, "{apex}");
        // Tangent-continuous junctions: vertical at both ends of the ellipse.
        assert!((g.tangent(80.0 + 1e-6) - v(0., 0., 1.)).norm() < 1e-3);
        assert!((g.tangent(425.197 - 1e-6) - v(0., 0., -1.)).norm() < 1e-3);
        // r = 10: same geometry, no stops, windows r_eff = 10 outside IP1/IP2.
        let g10 = pick_place(
            &p,
            &ShapeParams {
                elliptical: true,
                blending_radius: 10.0,
                z_dist_elliptical: 60.0,
            },
        );
        assert!((g10.length - g.length).abs() < 1e-9);
        assert_eq!(g10.stops.len(), 1);
        assert!(
            (g10.orientation_window.0 - 10.0).abs() < 1e-9
                && (g10.orientation_window.1 - 435.197).abs() < 1e-3
        );
    }

    #[test]
    fn height_zero_windows_follow_the_delta_rule() {
        // §7.5: IP1 ≡ S with r > 0 → windows start r after S; r = 0 → the coupling window
        // starts 0.1·window later (linear).
        let p = ProfilePoints {
            s: v(0., 0., 100.),
            ip1: v(0., 0., 100.),
            ip2: v(100., 0., 100.),
            t: v(100., 0., 50.),
        };
        let g = pick_place(
            &p,
            &ShapeParams {
                elliptical: false,
                blending_radius: 10.0,
                z_dist_elliptical: 0.0,
            },
        );
        assert!((g.orientation_window.0 - 10.0).abs() < 1e-9);
        let g0 = pick_place(
            &p,
            &ShapeParams {
                elliptical: false,
                blending_radius: 0.0,
                z_dist_elliptical: 0.0,
            },
        );
        assert_eq!(g0.orientation_window, (0.0, 100.0));
        assert!(
            (g0.coupling_window.0 - 10.0).abs() < 1e-9
                && (g0.coupling_window.1 - 100.0).abs() < 1e-9
        );
        assert_eq!(g0.point_arcs[0], 0.0, "IP1 ≡ S is passed at once");
    }

    #[test]
    fn coupling_factor_is_c2_smooth_quintic() {
        let p = ProfilePoints {
            s: v(0., 0., 0.),
            ip1: v(0., 0., 10.),
            ip2: v(100., 0., 10.),
            t: v(100., 0., 0.),
        };
        let g = pick_place(
            &p,
            &ShapeParams {
                elliptical: false,
                blending_radius: 0.0,
                z_dist_elliptical: 0.0,
            },
        );
        let (w0, w1) = g.coupling_window;
        assert_eq!(g.coupling(w0), 0.0);
        assert_eq!(g.coupling(w1), 1.0);
        assert!((g.coupling(0.5 * (w0 + w1)) - 0.5).abs() < 1e-12);
        assert!(
            g.coupling_slope(w0 + 1e-9).abs() < 1e-9 && g.coupling_slope(w1 - 1e-9).abs() < 1e-9
        );
    }

    #[test]
    fn arc_length_inverse_is_consistent() {
        let p = ProfilePoints {
            s: v(0., 0., 100.),
            ip1: v(0., 0., 120.),
            ip2: v(300., 0., 180.),
            t: v(300., 0., 140.),
        };
        let g = pick_place(
            &p,
            &ShapeParams {
                elliptical: true,
                blending_radius: 0.0,
                z_dist_elliptical: 60.0,
            },
        );
        // Chord sums between dense samples approach the arc length from below.
        let n = 20000;
        let mut chord = 0.0;
        for i in 0..n {
            chord += (g.position(g.length * (i + 1) as f64 / n as f64)
                - g.position(g.length * i as f64 / n as f64))
            .norm();
        }
        assert!((chord - g.length).abs() < 1e-3, "{chord} vs {}", g.length);
    }
}
