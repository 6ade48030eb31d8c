//! Track geometry (xplanar.md §1.6, §5.4): lines, circular arcs and generated C² transitions,
//! parameterised by arc length `s` from the track start.
//!
//! Transitions are the spec's quintic Hermite curves (`r(0)=P0, r(1)=P1, r'=D·t,
//! r''=κ·D²·n` at both ends); collinear ones degenerate to exact lines. Their arc length is
//! tabulated once (Gauss–Legendre per table interval) and inverted by cubic Hermite
//! interpolation of `u(s)`, so evaluating a pose on the cycle path is a table look-up and one
//! polynomial (no alloc, no lock).

use crate::geometry::V2;

/// Positions closer than this are "the same point" \[mm\] (§3.3 AppendLine).
pub const SAME_POINT: f64 = 1e-6;
/// Headings closer than this are continuous \[rad\].
pub const HEADING_TOL: f64 = 1e-6;
/// Curvatures closer than this are continuous \[1/mm\].
pub const CURVATURE_TOL: f64 = 1e-9;
/// Radius mismatch tolerated by AppendCircle \[mm\] (§3.3).
pub const RADIUS_TOL: f64 = 0.01;
/// Table intervals of a transition's arc-length table.
const TABLE: usize = 128;

/// A point on a track: position, heading (unit tangent angle) \[rad\] and signed curvature
/// (left turn positive) \[1/mm\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackPose {
    /// Position \[mm\].
    pub p: V2,
    /// Heading \[rad\].
    pub theta: f64,
    /// Curvature \[1/mm\].
    pub kappa: f64,
}

impl TrackPose {
    /// Unit tangent.
    pub fn tangent(&self) -> V2 {
        V2::new(self.theta.cos(), self.theta.sin())
    }

    /// Heading in degrees.
    pub fn heading_deg(&self) -> f64 {
        self.theta.to_degrees()
    }

    /// True if position, heading and curvature agree (the C² rule of §5.4).
    pub fn continuous_with(&self, o: &TrackPose) -> bool {
        (self.p - o.p).norm() <= SAME_POINT
            && angle_diff(self.theta, o.theta).abs() <= HEADING_TOL
            && (self.kappa - o.kappa).abs() <= CURVATURE_TOL
    }
}

/// `a − b` wrapped into (−π, π].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    if d > std::f64::consts::PI {
        d - std::f64::consts::TAU
    } else {
        d
    }
}

/// Why a geometry call failed (mapped to E_GEOMETRY_INVALID by the engine).
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryError(pub String);

/// The quintic Hermite transition in power form with its arc-length table.
#[derive(Clone, Debug)]
pub struct Transition {
    c: [V2; 6],
    /// (s_k, u_k, du/ds_k) at the table nodes.
    table: Vec<(f64, f64, f64)>,
    len: f64,
}

const GL5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_08),
    (0.906_179_845_938_664, 0.236_926_885_056_189_08),
];

impl Transition {
    fn new(a: &TrackPose, b: &TrackPose) -> Result<Transition, GeometryError> {
        let d = (b.p - a.p).norm();
        let (t0, t1) = (a.tangent(), b.tangent());
        let (n0, n1) = (V2::new(-t0.y, t0.x), V2::new(-t1.y, t1.x));
        let (p0, p1) = (a.p, b.p);
        let (v0, v1) = (t0 * d, t1 * d);
        let (a0, a1) = (n0 * (a.kappa * d * d), n1 * (b.kappa * d * d));
        let c = [
            p0,
            v0,
            a0 * 0.5,
            -p0 * 10.0 - v0 * 6.0 - a0 * 1.5 + a1 * 0.5 - v1 * 4.0 + p1 * 10.0,
            p0 * 15.0 + v0 * 8.0 + a0 * 1.5 - a1 + v1 * 7.0 - p1 * 15.0,
            -p0 * 6.0 - v0 * 3.0 - a0 * 0.5 + a1 * 0.5 - v1 * 3.0 + p1 * 6.0,
        ];
        let mut t = Transition {
            c,
            table: Vec::with_capacity(TABLE + 1),
            len: 0.0,
        };
        // Reversal / cusp check (§5.4): the tangent may turn, but never vanish or flip
        // between neighbouring samples.
        let mut prev = t.d1(0.0);
        for k in 1..=4 * TABLE {
            let u = k as f64 / (4 * TABLE) as f64;
            let cur = t.d1(u);
            if cur.norm() < 1e-6 * d || cur.dot(&prev) <= 0.0 {
                return Err(GeometryError(format!(
                    "generated transition from ({:.3}, {:.3}) to ({:.3}, {:.3}) reverses direction",
                    p0.x, p0.y, p1.x, p1.y
                )));
            }
            prev = cur;
        }
        let mut s = 0.0;
        t.table.push((0.0, 0.0, 1.0 / t.d1(0.0).norm()));
        for k in 0..TABLE {
            let (ua, ub) = (k as f64 / TABLE as f64, (k + 1) as f64 / TABLE as f64);
            s += t.integrate(ua, ub);
            t.table.push((s, ub, 1.0 / t.d1(ub).norm()));
        }
        t.len = s;
        Ok(t)
    }

    fn r(&self, u: f64) -> V2 {
        let c = &self.c;
        ((((c[5] * u + c[4]) * u + c[3]) * u + c[2]) * u + c[1]) * u + c[0]
    }

    fn d1(&self, u: f64) -> V2 {
        let c = &self.c;
        (((c[5] * (5.0 * u) + c[4] * 4.0) * u + c[3] * 3.0) * u + c[2] * 2.0) * u + c[1]
    }

    fn d2(&self, u: f64) -> V2 {
        let c = &self.c;
        ((c[5] * (20.0 * u) + c[4] * 12.0) * u + c[3] * 6.0) * u + c[2] * 2.0
    }

    fn integrate(&self, ua: f64, ub: f64) -> f64 {
        let (m, h) = ((ua + ub) / 2.0, (ub - ua) / 2.0);
        GL5.iter()
            .map(|(x, w)| w * self.d1(m + h * x).norm())
            .sum::<f64>()
            * h
    }

    /// Curve parameter at arc length `s` ∈ [0, len].
    fn u_at(&self, s: f64) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= self.len {
            return 1.0;
        }
        let k = self.table.partition_point(|e| e.0 <= s).clamp(1, TABLE) - 1;
        let (s0, u0, m0) = self.table[k];
        let (s1, u1, m1) = self.table[k + 1];
        let h = s1 - s0;
        let x = (s - s0) / h;
        let (x2, x3) = (x * x, x * x * x);
        let u = (2.0 * x3 - 3.0 * x2 + 1.0) * u0
            + (x3 - 2.0 * x2 + x) * h * m0
            + (-2.0 * x3 + 3.0 * x2) * u1
            + (x3 - x2) * h * m1;
        // One Newton step on the exact integral tightens the interpolation.
        let f = s0 + self.integrate(u0, u) - s;
        (u - f / self.d1(u).norm()).clamp(u0, u1)
    }

    fn pose_u(&self, u: f64) -> TrackPose {
        let d1 = self.d1(u);
        let d2 = self.d2(u);
        let n = d1.norm();
        TrackPose {
            p: self.r(u),
            theta: d1.y.atan2(d1.x),
            kappa: (d1.x * d2.y - d1.y * d2.x) / (n * n * n),
        }
    }
}

/// One segment of a track.
#[derive(Clone, Debug)]
pub enum Segment {
    /// Straight line from `p0` along unit `u`.
    Line {
        /// Start point.
        p0: V2,
        /// Unit direction.
        u: V2,
        /// Length \[mm\].
        len: f64,
    },
    /// Circular arc around `c` with radius `r`, starting at angle `phi0`, sweeping `sweep`
    /// (positive = counter-clockwise) \[rad\].
    Arc {
        /// Centre.
        c: V2,
        /// Radius \[mm\].
        r: f64,
        /// Start angle \[rad\].
        phi0: f64,
        /// Signed sweep \[rad\].
        sweep: f64,
    },
    /// Generated C² transition.
    Transition(Box<Transition>),
}

impl Segment {
    /// Arc length \[mm\].
    pub fn len(&self) -> f64 {
        match self {
            Segment::Line { len, .. } => *len,
            Segment::Arc { r, sweep, .. } => r * sweep.abs(),
            Segment::Transition(t) => t.len,
        }
    }

    /// Pose at local arc length `s` ∈ [0, len].
    pub fn pose(&self, s: f64) -> TrackPose {
        match self {
            Segment::Line { p0, u, .. } => TrackPose {
                p: p0 + u * s,
                theta: u.y.atan2(u.x),
                kappa: 0.0,
            },
            Segment::Arc { c, r, phi0, sweep } => {
                let sg = sweep.signum();
                let phi = phi0 + sg * s / r;
                TrackPose {
                    p: c + V2::new(phi.cos(), phi.sin()) * *r,
                    theta: phi + sg * std::f64::consts::FRAC_PI_2,
                    kappa: sg / r,
                }
            }
            Segment::Transition(t) => t.pose_u(t.u_at(s)),
        }
    }

    /// Local arc length of the point closest to `q` (ties: smallest) and its distance.
    fn closest(&self, q: V2) -> (f64, f64) {
        match self {
            Segment::Line { p0, u, len } => {
                let s = (q - p0).dot(u).clamp(0.0, *len);
                (s, (p0 + u * s - q).norm())
            }
            Segment::Arc { c, r, phi0, sweep } => {
                let mut best = (0.0, (self.pose(0.0).p - q).norm());
                let l = self.len();
                let e = (self.pose(l).p - q).norm();
                if e < best.1 {
                    best = (l, e);
                }
                let d = q - c;
                if d.norm() > 1e-12 {
                    let phi = d.y.atan2(d.x);
                    let rel = (sweep.signum() * (phi - phi0)).rem_euclid(std::f64::consts::TAU);
                    if rel <= sweep.abs() {
                        let s = rel * r;
                        let dist = (d.norm() - r).abs();
                        if dist < best.1 - 1e-12 || (dist <= best.1 + 1e-12 && s < best.0) {
                            best = (s, dist);
                        }
                    }
                }
                best
            }
            Segment::Transition(t) => {
                // Sample the table nodes, then refine by golden-section search around the best.
                let mut bk = 0;
                let mut bd = f64::INFINITY;
                for (k, e) in t.table.iter().enumerate() {
                    let d = (t.r(e.1) - q).norm();
                    if d < bd - 1e-12 {
                        bd = d;
                        bk = k;
                    }
                }
                let lo = t.table[bk.saturating_sub(1)].0;
                let hi = t.table[(bk + 1).min(TABLE)].0;
                let f = |s: f64| (t.pose_u(t.u_at(s)).p - q).norm();
                let (mut a, mut b) = (lo, hi);
                let g = 0.618_033_988_749_895;
                for _ in 0..60 {
                    let x1 = b - g * (b - a);
                    let x2 = a + g * (b - a);
                    if f(x1) <= f(x2) {
                        b = x2;
                    } else {
                        a = x1;
                    }
                }
                let s = (a + b) / 2.0;
                let d = f(s);
                if d < bd {
                    (s, d)
                } else {
                    (t.table[bk].0, bd)
                }
            }
        }
    }
}

/// The geometry of one track.
#[derive(Clone, Debug, Default)]
pub struct TrackGeometry {
    segs: Vec<Segment>,
    /// Arc length at the start of each segment.
    starts: Vec<f64>,
    len: f64,
    start: Option<TrackPose>,
    end: Option<TrackPose>,
    closed: bool,
}

impl TrackGeometry {
    /// Nothing appended yet (no start point).
    pub fn is_empty(&self) -> bool {
        self.start.is_none()
    }

    /// Total arc length \[mm\].
    pub fn length(&self) -> f64 {
        self.len
    }

    /// Closed by CloseLoop.
    pub fn closed(&self) -> bool {
        self.closed
    }

    /// Start pose (None when empty).
    pub fn start_pose(&self) -> Option<TrackPose> {
        self.start
    }

    /// End pose (None when empty).
    pub fn end_pose(&self) -> Option<TrackPose> {
        self.end
    }

    /// The segments.
    pub fn segments(&self) -> &[Segment] {
        &self.segs
    }

    /// Arc lengths of every junction between segments (including a closed loop's seam).
    pub fn junctions(&self) -> Vec<f64> {
        self.starts.iter().skip(1).copied().collect()
    }

    fn push(&mut self, seg: Segment) {
        self.starts.push(self.len);
        self.len += seg.len();
        let l = seg.len();
        self.end = Some(seg.pose(l));
        self.segs.push(seg);
    }

    /// Sets the start pose of an empty track.
    pub fn set_start(&mut self, pose: TrackPose) {
        self.start = Some(pose);
        self.end = Some(pose);
    }

    /// Appends a generated C² transition from the current end to `to` (nothing if they
    /// already agree); same point with a different heading/curvature is invalid.
    pub fn transition_to(&mut self, to: &TrackPose) -> Result<(), GeometryError> {
        let e = self
            .end
            .ok_or_else(|| GeometryError("track is empty".into()))?;
        let d = (to.p - e.p).norm();
        if d <= SAME_POINT {
            if e.continuous_with(&TrackPose { p: e.p, ..*to }) {
                return Ok(());
            }
            return Err(GeometryError(format!(
                "junction at ({:.3}, {:.3}) not C²: heading {:.6}° vs {:.6}°, curvature {:.3e} vs {:.3e}",
                e.p.x,
                e.p.y,
                e.theta.to_degrees(),
                to.theta.to_degrees(),
                e.kappa,
                to.kappa
            )));
        }
        let chord = (to.p - e.p) / d;
        let collinear = e.kappa.abs() <= CURVATURE_TOL
            && to.kappa.abs() <= CURVATURE_TOL
            && (e.tangent() - chord).norm() <= 1e-9
            && (to.tangent() - chord).norm() <= 1e-9;
        if collinear {
            self.push(Segment::Line {
                p0: e.p,
                u: chord,
                len: d,
            });
        } else {
            let t = Transition::new(&e, to)?;
            self.push(Segment::Transition(Box::new(t)));
        }
        // Snap the end onto the requested pose (the curve ends there analytically).
        self.end = Some(*to);
        Ok(())
    }

    /// `AppendPosition` (§3.3): start point on an empty track, else a transition arriving
    /// at `p` with heading `heading` \[rad\] and curvature 0.
    pub fn append_position(&mut self, p: V2, heading: f64) -> Result<(), GeometryError> {
        let pose = TrackPose {
            p,
            theta: heading,
            kappa: 0.0,
        };
        if self.is_empty() {
            self.set_start(pose);
            Ok(())
        } else {
            self.transition_to(&pose)
        }
    }

    /// `AppendLine(start, end)` (§3.3).
    pub fn append_line(&mut self, a: V2, b: V2) -> Result<(), GeometryError> {
        let d = (b - a).norm();
        if d <= SAME_POINT {
            return Err(GeometryError("zero-length line".into()));
        }
        let u = (b - a) / d;
        let pose = TrackPose {
            p: a,
            theta: u.y.atan2(u.x),
            kappa: 0.0,
        };
        if self.is_empty() {
            self.set_start(pose);
        } else {
            self.transition_to(&pose)?;
        }
        self.push(Segment::Line { p0: a, u, len: d });
        self.end = Some(TrackPose { p: b, ..pose });
        Ok(())
    }

    /// `AppendCircle(start, end, center, clockwise)` (§3.3); start = end is a full circle.
    pub fn append_circle(
        &mut self,
        a: V2,
        b: V2,
        c: V2,
        clockwise: bool,
    ) -> Result<(), GeometryError> {
        let r = (a - c).norm();
        let rb = (b - c).norm();
        if r <= SAME_POINT {
            return Err(GeometryError("radius 0".into()));
        }
        if (r - rb).abs() > RADIUS_TOL {
            return Err(GeometryError(format!(
                "|start - center| = {r:.4} differs from |end - center| = {rb:.4}"
            )));
        }
        let sg = if clockwise { -1.0 } else { 1.0 };
        let phi0 = (a - c).y.atan2((a - c).x);
        let phi1 = (b - c).y.atan2((b - c).x);
        let mut sweep = (sg * (phi1 - phi0)).rem_euclid(std::f64::consts::TAU);
        if sweep * r <= SAME_POINT {
            sweep = std::f64::consts::TAU;
        }
        let seg = Segment::Arc {
            c,
            r,
            phi0,
            sweep: sg * sweep,
        };
        let pose = seg.pose(0.0);
        if self.is_empty() {
            self.set_start(pose);
        } else {
            self.transition_to(&pose)?;
        }
        let end = seg.pose(seg.len());
        self.push(seg);
        self.end = Some(TrackPose { p: b, ..end });
        Ok(())
    }

    /// `CloseLoop` (§3.3): transition end → start if needed; the track becomes a loop.
    pub fn close_loop(&mut self) -> Result<(), GeometryError> {
        let s = self
            .start
            .ok_or_else(|| GeometryError("empty track".into()))?;
        if self.closed {
            return Err(GeometryError("already a closed loop".into()));
        }
        self.transition_to(&s)?;
        if self.len <= SAME_POINT {
            return Err(GeometryError("loop of zero length".into()));
        }
        self.closed = true;
        self.end = Some(s);
        Ok(())
    }

    /// Index of the segment holding `s` (clamped into [0, L]).
    fn seg_at(&self, s: f64) -> (usize, f64) {
        let k = self.starts.partition_point(|&x| x <= s).max(1) - 1;
        (k, (s - self.starts[k]).clamp(0.0, self.segs[k].len()))
    }

    /// Pose at arc length `s`; closed loops wrap, open tracks clamp to [0, L] (no alloc).
    pub fn pose_at(&self, s: f64) -> TrackPose {
        if self.segs.is_empty() {
            return self.start.unwrap_or(TrackPose {
                p: V2::zeros(),
                theta: 0.0,
                kappa: 0.0,
            });
        }
        let s = if self.closed {
            s.rem_euclid(self.len)
        } else {
            s.clamp(0.0, self.len)
        };
        let (k, l) = self.seg_at(s);
        self.segs[k].pose(l)
    }

    /// Pose at the junction `s` seen from the segment before (`before`) or after it.
    pub fn pose_at_side(&self, s: f64, before: bool) -> TrackPose {
        let k = self
            .starts
            .iter()
            .position(|&x| (x - s).abs() < 1e-9)
            .unwrap_or(0);
        if before {
            let kb = if k == 0 { self.segs.len() - 1 } else { k - 1 };
            let seg = &self.segs[kb];
            seg.pose(seg.len())
        } else {
            self.segs[k].pose(0.0)
        }
    }

    /// `GetArcLengthClosestTo` (§3.3): the arc length closest to `q`; ties → smallest.
    pub fn closest(&self, q: V2) -> f64 {
        let mut best = (0.0, f64::INFINITY);
        for (k, seg) in self.segs.iter().enumerate() {
            let (s, d) = seg.closest(q);
            if d < best.1 - 1e-9 {
                best = (self.starts[k] + s, d);
            }
        }
        if self.segs.is_empty() {
            return 0.0;
        }
        if self.closed && (best.0 - self.len).abs() < 1e-9 {
            0.0
        } else {
            best.0
        }
    }

    /// Points every `step` mm along the track (for the on-part check at Enable).
    pub fn samples(&self, step: f64) -> Vec<V2> {
        let n = (self.len / step).ceil().max(1.0) as usize;
        (0..=n)
            .map(|k| self.pose_at(self.len * k as f64 / n as f64).p)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collinear_transition_is_exact() {
        let mut g = TrackGeometry::default();
        g.append_line(V2::new(40.0, 120.0), V2::new(240.0, 120.0))
            .unwrap();
        g.append_line(V2::new(260.0, 120.0), V2::new(440.0, 120.0))
            .unwrap();
        assert_eq!(g.length(), 400.0);
    }

    #[test]
    fn corner_transition_is_c2_and_arc_length_consistent() {
        let mut g = TrackGeometry::default();
        g.append_line(V2::new(0.0, 0.0), V2::new(400.0, 0.0))
            .unwrap();
        g.append_line(V2::new(500.0, 100.0), V2::new(500.0, 400.0))
            .unwrap();
        for s in g.junctions() {
            let a = g.pose_at_side(s, true);
            let b = g.pose_at_side(s, false);
            assert!(a.continuous_with(&b), "junction {s}: {a:?} vs {b:?}");
        }
        // Sum of chord lengths converges to the arc length.
        let n = 20000;
        let mut acc = 0.0;
        let mut prev = g.pose_at(0.0).p;
        for k in 1..=n {
            let p = g.pose_at(g.length() * k as f64 / n as f64).p;
            acc += (p - prev).norm();
            prev = p;
        }
        assert!((acc - g.length()).abs() < 1e-3, "{acc} vs {}", g.length());
    }

    #[test]
    fn circle_and_closest() {
        let mut g = TrackGeometry::default();
        g.append_circle(V2::new(100.0, 0.0), V2::new(100.0, 0.0), V2::zeros(), false)
            .unwrap();
        assert!((g.length() - 200.0 * std::f64::consts::PI).abs() < 1e-9);
        let s = g.closest(V2::new(0.0, 300.0));
        assert!((s - 50.0 * std::f64::consts::PI).abs() < 1e-6);
    }
}
