//! The CA follower planner (collision_avoidance.md §8.4–§8.6): one jerk-limited step of one
//! axis in its travel frame, bounded by its command (C2, C3) and by the pair constraint C4.
//!
//! Everything here works in a *forward frame*: the axis moves (or is about to move) in the
//! positive direction, `v ≥ 0`. The caller mirrors backward motion (`x → −x`). No alloc, no lock.

/// Kinematic state of one axis \[mm, mm/s, mm/s²\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kin {
    /// Position \[mm\].
    pub x: f64,
    /// Velocity \[mm/s\].
    pub v: f64,
    /// Acceleration \[mm/s²\].
    pub a: f64,
}

impl Kin {
    /// At rest at `x`.
    pub fn rest(x: f64) -> Self {
        Kin { x, v: 0.0, a: 0.0 }
    }
    /// Mirror image (`x → −x`).
    pub fn mirror(self) -> Self {
        Kin {
            x: -self.x,
            v: -self.v,
            a: -self.a,
        }
    }
    /// v = a = 0.
    pub fn at_rest(&self) -> bool {
        self.v == 0.0 && self.a == 0.0
    }
}

/// Exact integration of a constant jerk `j` over `t`.
#[inline]
pub fn integrate(s: Kin, j: f64, t: f64) -> Kin {
    Kin {
        x: s.x + t * (s.v + t * (s.a / 2.0 + t * j / 6.0)),
        v: s.v + t * (s.a + t * j / 2.0),
        a: s.a + j * t,
    }
}

/// The jerk-limited braking profile P of §8.4 from `(v ≥ 0, a)` with limits `(d, jm)`: up to
/// four constant-jerk phases `(jerk, duration)`.
#[inline]
fn brake_phases(v: f64, a: f64, d: f64, jm: f64) -> ([(f64, f64); 4], usize) {
    let mut ph = [(0.0, 0.0); 4];
    let mut n = 0;
    let mut v = v.max(0.0);
    let mut d0 = -a;
    if a > 0.0 {
        ph[n] = (-jm, a / jm);
        n += 1;
        v += a * a / (2.0 * jm);
        d0 = 0.0;
    }
    if v <= d0 * d0 / (2.0 * jm) {
        let t = (d0 - (d0 * d0 - 2.0 * jm * v).max(0.0).sqrt()) / jm;
        ph[n] = (jm, t.max(0.0));
        n += 1;
    } else if d0 > d {
        ph[n] = (jm, (d0 - d) / jm);
        ph[n + 1] = (0.0, ((v - d0 * d0 / (2.0 * jm)) / d).max(0.0));
        ph[n + 2] = (jm, d / jm);
        n += 3;
    } else {
        let dp = (jm * v + d0 * d0 / 2.0).sqrt();
        if dp <= d {
            ph[n] = (-jm, ((dp - d0) / jm).max(0.0));
            ph[n + 1] = (jm, dp / jm);
            n += 2;
        } else {
            ph[n] = (-jm, ((d - d0) / jm).max(0.0));
            ph[n + 1] = (
                0.0,
                ((v - (2.0 * d * d - d0 * d0) / (2.0 * jm)) / d).max(0.0),
            );
            ph[n + 2] = (jm, d / jm);
            n += 3;
        }
    }
    (ph, n)
}

/// `StopPoint(x, v, a; D, J)` for forward motion (`v ≥ 0`): where the braking profile P ends.
#[inline]
pub fn stop_point(s: Kin, d: f64, jm: f64) -> f64 {
    if s.v <= 0.0 && s.a <= 0.0 {
        return s.x;
    }
    let (ph, n) = brake_phases(s.v, s.a, d, jm);
    let mut k = s;
    for &(j, t) in &ph[..n] {
        k = integrate(k, j, t);
    }
    k.x
}

/// `StopPoint(s; d, jm) ≤ bound`, with a cheap sufficient test first: the stop distance is
/// at most `v_peak · (a⁺/J + v_peak/D + D/J)` (AM-GM bounds the triangular case) when the
/// deceleration does not exceed `d` (else the exact stop point decides). No alloc.
#[inline]
pub fn stop_point_le(s: Kin, d: f64, jm: f64, bound: f64) -> bool {
    if s.a >= -d {
        let ap = s.a.max(0.0);
        let v_peak = s.v.max(0.0) + ap * ap / (2.0 * jm);
        if s.x + v_peak * (ap / jm + v_peak / d + d / jm) <= bound {
            return true;
        }
    }
    stop_point(s, d, jm) <= bound
}

/// `StopPoint` of a backward-moving state (mirror image).
#[inline]
pub fn stop_point_back(s: Kin, d: f64, jm: f64) -> f64 {
    -stop_point(s.mirror(), d, jm)
}

/// Advances exactly along the braking profile P for `t` (§8.5 step 7): phase switches inside
/// the cycle included; ends at rest at the stop point when the profile ends within `t`.
#[inline]
pub fn advance_brake(s: Kin, d: f64, jm: f64, t: f64) -> Kin {
    if s.v <= 0.0 && s.a <= 0.0 {
        return Kin::rest(s.x);
    }
    let (ph, n) = brake_phases(s.v, s.a, d, jm);
    let mut k = s;
    let mut left = t;
    for &(j, dur) in &ph[..n] {
        if dur >= left {
            let e = integrate(k, j, left);
            return Kin {
                v: e.v.max(0.0),
                ..e
            };
        }
        k = integrate(k, j, dur);
        left -= dur;
    }
    Kin::rest(k.x)
}

/// The pair constraint C4 in the forward frame: `x' ≤ pos_bound` and
/// `StopPoint(s'; D_b, J_b) ≤ stop_bound` (both already reduced by the gap).
#[derive(Clone, Copy, Debug)]
pub struct Bound {
    /// Bound on the end position of the cycle (Fast: predecessor's predicted position − gap).
    pub pos_bound: f64,
    /// Bound on the CA stop point (Standard: predecessor's position − gap).
    pub stop_bound: f64,
    /// Fast: the predecessor's hardest stop, for the sampled C4 when the follower's braking
    /// deceleration exceeds the predecessor's maximum (§8.6).
    pub lead: Option<Lead>,
}

/// The predecessor of a Fast pair as C4 sees it (forward frame): its hardest stop from
/// `(x, v)` with its maximum deceleration `d`, starting `t0` before the follower's end of
/// cycle (0: already updated this cycle; T: start-of-cycle state).
#[derive(Clone, Copy, Debug)]
pub struct Lead {
    /// Position minus the follower's gap \[mm\].
    pub x: f64,
    /// Velocity (≥ 0) \[mm/s\].
    pub v: f64,
    /// Maximum deceleration \[mm/s²\].
    pub d: f64,
    /// Age of the state at the follower's end of cycle \[s\].
    pub t0: f64,
}

impl Lead {
    /// Position (minus the gap) at `t` after the state, braking as hard as it can.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        let tau = t.min(self.v / self.d);
        self.x + self.v * tau - self.d * tau * tau / 2.0
    }
}

/// Samples in the sampled C4 before the rest of the follower's stop is taken in one piece
/// (conservative: the predecessor only advances).
const MAX_SAMPLES: usize = 100_000;

/// Sampled C4-Fast (§8.6): `max_i (x_f(iT) − x_l(t0 + iT))` over every future cycle instant
/// until both are at rest, the follower on its CA braking profile P(db, jb) from `s`, the
/// predecessor on its hardest stop; ≤ 0 ⇔ the gap holds at every sample. No alloc.
pub fn sampled_excess(s: Kin, db: f64, jb: f64, lead: &Lead, t: f64) -> f64 {
    let (ph, n) = if s.v <= 0.0 && s.a <= 0.0 {
        ([(0.0, 0.0); 4], 0)
    } else {
        brake_phases(s.v, s.a, db, jb)
    };
    let lead_stop = lead.v / lead.d;
    let mut worst = f64::NEG_INFINITY;
    let (mut k, mut tk, mut p) = (s, 0.0, 0);
    for i in 0..=MAX_SAMPLES {
        let ti = i as f64 * t;
        while p < n && tk + ph[p].1 <= ti {
            k = integrate(k, ph[p].0, ph[p].1);
            tk += ph[p].1;
            p += 1;
        }
        let xf = if p < n {
            integrate(k, ph[p].0, ti - tk).x
        } else {
            k.x
        };
        worst = worst.max(xf - lead.at(lead.t0 + ti));
        if p >= n {
            // The follower rests; the predecessor only moves on.
            return worst;
        }
        if lead.t0 + ti >= lead_stop || i == MAX_SAMPLES {
            // The predecessor rests (or the sampling budget is spent): the follower's stop
            // point against the predecessor's current, never decreasing, position.
            return worst.max(stop_point(s, db, jb) - lead.at(lead.t0 + ti));
        }
    }
    worst
}

/// Does the sampled C4 apply (the follower may brake harder than the predecessor can)?
#[inline]
fn sampled(b: &Bound, db: f64) -> Option<&Lead> {
    b.lead.as_ref().filter(|l| db > l.d)
}

/// Inputs of one axis step (forward frame).
#[derive(Clone, Copy, Debug)]
pub struct StepIn {
    /// Start-of-cycle state (`v ≥ 0`; `a ≥ 0` when `v = 0`).
    pub s: Kin,
    /// Velocity limit (× override) \[mm/s\].
    pub vmax: f64,
    /// Acceleration limit \[mm/s²\].
    pub amax: f64,
    /// Command deceleration \[mm/s²\].
    pub dmax: f64,
    /// Command jerk \[mm/s³\].
    pub jmax: f64,
    /// Position bound of the command (target); `None` = brake (halt/stop).
    pub target: Option<f64>,
    /// Committed CA braking deceleration and jerk (§8.4).
    pub d_ca: f64,
    /// Committed CA braking jerk.
    pub j_ca: f64,
    /// C4, if the axis has a responsible neighbour.
    pub c4: Option<Bound>,
    /// Cycle time \[s\].
    pub t: f64,
}

/// Result of one axis step.
#[derive(Clone, Copy, Debug)]
pub struct StepOut {
    /// New state.
    pub s: Kin,
    /// C4 bounded the motion in this cycle.
    pub ca_limited: bool,
    /// CA braking dynamics used for C4 this cycle (after the leftover rule).
    pub d_b: f64,
    /// Jerk counterpart of `d_b`.
    pub j_b: f64,
}

/// Standstill threshold of §8.5 step 0 \[mm\].
pub const START_THRESHOLD: f64 = 1e-4;
/// |v| [mm/s] and |a| [mm/s²] below which a planned state is standstill (numerical residue).
pub const REST_EPS: f64 = 1e-9;
/// Bisection steps: jerk resolution 2·J/2³² (< 1e-4 mm/s³ at J = 2e5).
const ITER: usize = 32;

/// C4 for a candidate state (forward frame).
#[inline]
pub fn c4_ok(b: &Bound, s: Kin, db: f64, jb: f64, t: f64) -> bool {
    match sampled(b, db) {
        Some(l) => sampled_excess(s, db, jb, l, t) <= 0.0,
        None => s.x <= b.pos_bound && stop_point_le(s, db, jb, b.stop_bound),
    }
}

/// C4 as a residual, increasing with the candidate's advance (≤ 0: holds).
#[inline]
fn c4_residual(b: &Bound, s: Kin, db: f64, jb: f64, t: f64) -> f64 {
    match sampled(b, db) {
        Some(l) => sampled_excess(s, db, jb, l, t),
        None => (s.x - b.pos_bound).max(stop_point(s, db, jb) - b.stop_bound),
    }
}

/// L(J′): no velocity sign change inside the cycle, end state not over-braked.
#[inline]
fn lower_ok(s: Kin, j: f64, t: f64, jp: f64) -> bool {
    let e = integrate(s, j, t);
    if e.v < 0.0 {
        return false;
    }
    if j > 0.0 && s.a < 0.0 && -s.a / j < t && s.v - s.a * s.a / (2.0 * j) < 0.0 {
        return false;
    }
    !(e.a < 0.0 && e.v < e.a * e.a / (2.0 * jp))
}

/// Smallest j in `[lo, hi]` satisfying L(J′) (None: none does).
#[inline]
fn lower_threshold(s: Kin, t: f64, lo: f64, hi: f64, jp: f64) -> Option<f64> {
    if lower_ok(s, lo, t, jp) {
        return Some(lo);
    }
    if !lower_ok(s, hi, t, jp) {
        return None;
    }
    let (mut a, mut b) = (lo, hi);
    for _ in 0..ITER {
        let m = 0.5 * (a + b);
        if lower_ok(s, m, t, jp) {
            b = m
        } else {
            a = m
        }
    }
    Some(b)
}

/// Largest j in `[jl, hi]` whose end state satisfies `upper` (monotone: true below a
/// threshold); None if not even `jl` does.
#[inline]
fn search_from(s: Kin, t: f64, jl: f64, hi: f64, upper: impl Fn(Kin) -> bool) -> Option<f64> {
    if upper(integrate(s, hi, t)) {
        return Some(hi);
    }
    if !upper(integrate(s, jl, t)) {
        return None;
    }
    let (mut a, mut b) = (jl, hi);
    for _ in 0..ITER {
        let m = 0.5 * (a + b);
        if upper(integrate(s, m, t)) {
            a = m
        } else {
            b = m
        }
    }
    Some(a)
}

/// Largest j in `[jl, hi]` with `f(end state) ≤ 0` for a continuous residual `f` increasing
/// in j (Illinois regula falsi: a few evaluations instead of a full bisection; the returned
/// j is always on the feasible side, within 1e-9 mm of the bound or the jerk resolution).
#[inline]
fn root_from(s: Kin, t: f64, jl: f64, hi: f64, f: impl Fn(Kin) -> f64) -> Option<f64> {
    let fb0 = f(integrate(s, hi, t));
    if fb0 <= 0.0 {
        return Some(hi);
    }
    let fa0 = f(integrate(s, jl, t));
    if fa0 > 0.0 {
        return None;
    }
    let (mut a, mut fa, mut b, mut fb) = (jl, fa0, hi, fb0);
    let width = (hi - jl).abs().max(1.0);
    let mut side = 0;
    for _ in 0..(2 * ITER) {
        if fa > -1e-9 || b - a <= width * 2f64.powi(-(ITER as i32)) {
            break;
        }
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
        }
        let fm = f(integrate(s, m, t));
        if fm <= 0.0 {
            a = m;
            fa = fm;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = m;
            fb = fm;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    Some(a)
}

/// The jerk at which C2 (`v' + a'|a'|/(2J) = V`) becomes tight, in closed form (numerically
/// stable roots of the two quadratic branches a' ≥ 0 and a' < 0).
#[inline]
fn c2_limit(s: Kin, vmax: f64, jm: f64, t: f64) -> Option<f64> {
    let al = t * t / (2.0 * jm);
    // Branch a' >= 0: al j² + be j + ga = 0.
    let be = t * t / 2.0 + s.a * t / jm;
    let ga = s.v + s.a * t + s.a * s.a / (2.0 * jm) - vmax;
    let disc = be * be - 4.0 * al * ga;
    if disc >= 0.0 {
        let den = be + disc.sqrt();
        if den > 0.0 {
            let j = -2.0 * ga / den;
            if s.a + j * t >= 0.0 {
                return Some(j);
            }
        }
    }
    // Branch a' < 0: -al j² + be2 j + ga2 = 0, increasing root.
    let be2 = t * t / 2.0 - s.a * t / jm;
    let ga2 = s.v + s.a * t - s.a * s.a / (2.0 * jm) - vmax;
    let disc2 = be2 * be2 + 4.0 * al * ga2;
    if disc2 >= 0.0 {
        let den = be2 + disc2.sqrt();
        if den > 0.0 {
            let j = -2.0 * ga2 / den;
            if s.a + j * t < 0.0 {
                return Some(j);
            }
        }
    }
    None
}

#[inline]
fn range(s: Kin, amax: f64, d: f64, jm: f64, t: f64) -> (f64, f64) {
    let lo = ((-d - s.a) / t).clamp(-jm, jm);
    let hi = ((amax - s.a) / t).clamp(-jm, jm).max(lo);
    (lo, hi)
}

/// One cycle of one axis (§8.5), forward frame.
pub fn step(p: &StepIn) -> StepOut {
    let s = p.s;
    let t = p.t;
    // Step 1: leftover rule.
    let (mut jn, dn) = if s.a < -p.dmax || (s.a < 0.0 && s.v < s.a * s.a / (2.0 * p.jmax)) {
        (p.jmax.max(p.j_ca), p.dmax.max(-s.a))
    } else {
        (p.jmax, p.dmax)
    };
    // The same for an acceleration left by a command with a higher jerk: ramping it down with
    // the new, softer jerk would overshoot the velocity limit.
    if s.a > 0.0 && s.v + s.a * s.a / (2.0 * p.jmax) > p.vmax {
        jn = jn.max(p.j_ca);
    }
    let db = p.d_ca.max(dn);
    let jb = p.j_ca.max(jn);
    let out = |s: Kin, lim: bool| StepOut {
        // A residue of the bound search (|v| and |a| far below one ULP of motion per cycle)
        // is standstill: else a follower waiting behind its leader keeps v ≈ 1e-12 forever
        // and the group never reports AllAxesStanding (§5.16).
        s: if s.v.abs() < REST_EPS && s.a.abs() < REST_EPS {
            Kin::rest(s.x)
        } else {
            s
        },
        ca_limited: lim,
        d_b: db,
        j_b: jb,
    };
    // Step 0: standstill threshold.
    if s.at_rest() {
        let Some(target) = p.target else {
            return out(s, false);
        };
        if target <= s.x {
            return out(s, false);
        }
        if target - s.x <= START_THRESHOLD {
            let ok =
                p.c4.is_none_or(|b| target <= b.pos_bound && target <= b.stop_bound);
            return if ok {
                out(Kin::rest(target), false)
            } else {
                out(s, true)
            };
        }
        if let Some(b) = p.c4 {
            let x1 = s.x + START_THRESHOLD;
            if !(x1 <= b.pos_bound && x1 <= b.stop_bound) {
                return out(s, true);
            }
        }
    }
    // Step 3: nominal jerk. C3 with the braking the *next* cycle will use (leftover rule on
    // the end state): otherwise the approach overshoots when the rule switches off.
    let c3 = |e: Kin, target: f64| {
        let j_next = if e.a < 0.0 && e.v < e.a * e.a / (2.0 * p.jmax) {
            p.jmax.max(p.j_ca)
        } else {
            p.jmax
        };
        stop_point_le(e, p.dmax.max(-e.a), j_next, target)
    };
    let c2 = |e: Kin| e.v + e.a * e.a.abs() / (2.0 * jn) <= p.vmax * (1.0 + 1e-12);
    let j_nom = p.target.and_then(|target| {
        let (lo, hi) = range(s, p.amax, dn, jn, t);
        // Fast path (cruise, acceleration): the C2 limit in closed form, then C3 checked once.
        let jl = lower_threshold(s, t, lo, hi, jn)?;
        let cand = c2_limit(s, p.vmax, jn, t).map_or(hi, |j| j.min(hi));
        if cand >= jl {
            let e = integrate(s, cand, t);
            if c2(e) && c3(e, target) {
                return Some(cand);
            }
        }
        search_from(s, t, jl, hi, |e| c2(e) && c3(e, target))
    });
    let brake_n = || advance_brake(s, dn, jn, t);
    let brake_b = || advance_brake(s, db, jb, t);
    // Step 4: the pair constraint.
    let mut j_ca = f64::INFINITY;
    if let Some(b) = p.c4 {
        if !c4_ok(&b, s, db, jb, t) {
            return out(brake_b(), true);
        }
        // Fast path: the nominal step keeps C4 (L(J_n) implies L(J_b), J_b ≥ J_n) ⇒ j_ca ≥ j_nom.
        if let Some(j) = j_nom {
            if c4_ok(&b, integrate(s, j, t), db, jb, t) {
                let mut e = integrate(s, j, t);
                if e.v < 0.0 {
                    e.v = 0.0;
                }
                return out(e, false);
            }
        }
        let (lo, hi) = range(s, p.amax, db, jb, t);
        let found = lower_threshold(s, t, lo, hi, jb)
            .and_then(|jl| root_from(s, t, jl, hi, |e| c4_residual(&b, e, db, jb, t)));
        match found {
            Some(j) => j_ca = j,
            None => {
                let e = brake_n();
                return if c4_ok(&b, e, db, jb, t) {
                    out(e, true)
                } else {
                    out(brake_b(), true)
                };
            }
        }
    }
    // Step 5: end of the approach (or a halt).
    let Some(j_nom) = j_nom else {
        let e = brake_n();
        if let Some(b) = p.c4 {
            if !c4_ok(&b, e, db, jb, t) {
                return out(brake_b(), true);
            }
        }
        return out(e, false);
    };
    // Step 6.
    let j = j_nom.min(j_ca);
    let mut e = integrate(s, j, t);
    if e.v < 0.0 {
        e.v = 0.0;
    }
    out(e, j_ca < j_nom)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stop_point_closed_form_from_cruise() {
        // v ≥ D²/J: v²/(2D) + v·D/(2J).
        let s = Kin {
            x: 0.0,
            v: 1000.0,
            a: 0.0,
        };
        let d = stop_point(s, 10000.0, 100000.0);
        assert!((d - (50.0 + 50.0)).abs() < 1e-9, "{d}");
        // v < D²/J: v·√(v/J).
        let s = Kin {
            x: 0.0,
            v: 100.0,
            a: 0.0,
        };
        let d = stop_point(s, 20000.0, 200000.0);
        assert!(
            (d - 100.0 * (100.0f64 / 200000.0).sqrt()).abs() < 1e-9,
            "{d}"
        );
    }

    #[test]
    fn single_axis_arrives_in_the_time_optimal_1_2_s() {
        // §8.5 prototype: 0 → 1000, V 1000, A = D 10000, J 100000: exactly 1.200 s.
        let mut s = Kin::rest(0.0);
        let mut n = 0;
        while !(s.at_rest() && (s.x - 1000.0).abs() <= 1e-6) && n < 5000 {
            let o = step(&StepIn {
                s,
                vmax: 1000.0,
                amax: 10000.0,
                dmax: 10000.0,
                jmax: 100000.0,
                target: Some(1000.0),
                d_ca: 10000.0,
                j_ca: 100000.0,
                c4: None,
                t: 0.001,
            });
            s = o.s;
            n += 1;
        }
        assert!(
            (1199..=1201).contains(&n),
            "arrived after {n} cycles at {s:?}"
        );
    }
}
