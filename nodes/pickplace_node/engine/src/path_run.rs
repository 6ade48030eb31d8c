//! Motion along a planned path (pick_and_place.md §7.7 – §7.8, §9, §12, §15.1): rest-to-rest
//! jerk-limited sub-profiles of the path parameter σ (with `motion_core::trajectory::Profile1`),
//! axis-limit reduction, override, path-true stop/hold/resume, and the frame-coupling model
//! P(t) = G(σ) + (1 − k)·Δ_A(t) + k·Δ_B(t).

use crate::geometry::{PathGeometry, Vec3, LENGTH_EPS};
use crate::params::ScPar;
use motion_core::trajectory::{Limits, Profile1, State1};

/// `T_ramp(w, α)` of §7.7: time to ramp between 0 and w with max acceleration α and jerk j.
pub fn t_ramp(w: f64, alpha: f64, j: f64) -> f64 {
    if w >= alpha * alpha / j {
        w / alpha + alpha / j
    } else {
        2.0 * (w / j).sqrt()
    }
}

/// `D_ramp(w, α)` of §7.7: distance of that ramp.
pub fn d_ramp(w: f64, alpha: f64, j: f64) -> f64 {
    if w >= alpha * alpha / j {
        0.5 * w * (w / alpha + alpha / j)
    } else {
        w * (w / j).sqrt()
    }
}

/// Rest-to-rest duration of §7.7 for arc length `l` (closed form; cross-check of Profile1).
pub fn rest_to_rest_time(l: f64, lim: &Limits) -> f64 {
    let (v, a, d, j) = (lim.velocity, lim.acceleration, lim.deceleration, lim.jerk);
    if d_ramp(v, a, j) + d_ramp(v, d, j) <= l {
        return l / v + 0.5 * (t_ramp(v, a, j) + t_ramp(v, d, j));
    }
    // Peak velocity below v: bisection on D_ramp(vp, a) + D_ramp(vp, d) = L.
    let (mut lo, mut hi) = (0.0, v);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if d_ramp(m, a, j) + d_ramp(m, d, j) > l {
            hi = m;
        } else {
            lo = m;
        }
    }
    t_ramp(lo, a, j) + t_ramp(lo, d, j)
}

/// A frame that moves with a belt: Δ(t) = dir·(s(t) − s_ref) + c (§15.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingFrame {
    /// Belt number 1 … 16.
    pub belt: usize,
    /// Running direction in MCS.
    pub dir: Vec3,
    /// Belt position of the reference.
    pub s_ref: f64,
    /// Constant offset (prediction error of X̂_B).
    pub c: Vec3,
}

impl MovingFrame {
    /// Δ at belt position `s`.
    pub fn delta(&self, s: f64) -> Vec3 {
        self.dir * (s - self.s_ref) + self.c
    }
}

/// How the path parameter is currently driven.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drive {
    /// Following the current sub-profile towards its stop point.
    Run,
    /// Braking path-true (stop, halt, interrupt, override 0).
    Stopping,
    /// At rest on the path, waiting for a resume.
    Held,
    /// All sub-profiles done.
    Finished,
}

/// Effective path limits of a σ range after the axis-limit reduction of §7.8 (ov = 1).
pub fn effective_limits(
    par: &ScPar,
    geom: &PathGeometry,
    s0: f64,
    s1: f64,
    start: &[f64; 7],
    end: &[f64; 7],
) -> Limits {
    let mut c = [0.0f64; 7];
    let xyz = geom.max_tangent_components(s0, s1);
    c[..3].copy_from_slice(&xyz);
    let (w0, w1) = geom.orientation_window;
    if w1 - w0 > LENGTH_EPS && s1 > w0 && s0 < w1 {
        for q in 3..7 {
            c[q] = (end[q] - start[q]).abs() / (w1 - w0);
        }
    }
    let reduce = |base: f64, maxes: &[f64; 7]| {
        let mut v = base;
        for q in 0..7 {
            if maxes[q] > 0.0 && c[q] > 1e-12 {
                v = v.min(maxes[q] / c[q]);
            }
        }
        v
    };
    Limits {
        velocity: reduce(par.path_vel, &par.max_vel),
        acceleration: reduce(par.path_acc, &par.max_acc_dec),
        deceleration: reduce(par.path_dec, &par.max_acc_dec),
        jerk: reduce(par.path_jerk, &par.max_jerk),
    }
}

fn scaled(l: &Limits, ov: f64) -> Limits {
    Limits {
        velocity: l.velocity * ov,
        acceleration: l.acceleration * ov,
        deceleration: l.deceleration * ov,
        jerk: l.jerk * ov,
    }
}

/// Override below which the path is brought to standstill instead of scaled (§12: 0 = halt).
const OV_STANDSTILL: f64 = 1e-6;

/// The mutable progress of a [`PathRun`] (no allocation to save or restore): lets the cycle try
/// a shorter advance of the path parameter (§7.8 (2)) and take it back.
#[derive(Clone, Copy, Debug)]
pub struct Cursor {
    sub: usize,
    motion: Profile1,
    t: f64,
    sigma: State1,
    drive: Drive,
    nominal: bool,
    ov_hold: bool,
}

/// One path in execution.
#[derive(Clone, Debug)]
pub struct PathRun {
    /// Geometry in the planning snapshot.
    pub geom: PathGeometry,
    /// Pose (X … C, Aux1) at S; orientation/Aux1 before the window.
    pub start_pose: [f64; 7],
    /// Pose at T; orientation/Aux1 after the window.
    pub end_pose: [f64; 7],
    /// Frame of the start if it moves (belt), else MCS.
    pub frame_a: Option<MovingFrame>,
    /// Frame of the target if it moves (belt), else MCS.
    pub frame_b: Option<MovingFrame>,
    /// Limits per sub-profile at override 1.
    pub limits: Vec<Limits>,
    /// Planned sub-profiles at override 1 (rest to rest).
    pub plans: Vec<Profile1>,
    /// Index of the current sub-profile.
    pub sub: usize,
    motion: Profile1,
    t: f64,
    /// Path state σ, σ', σ''.
    pub sigma: State1,
    /// Current drive mode.
    pub drive: Drive,
    ov: f64,
    /// The current sub-profile runs its original ov = 1 plan (gripper timing is exact).
    nominal: bool,
    /// Held only because the override is 0.
    ov_hold: bool,
    /// S, IP1, IP2, T of a pick & place leg (for the resume after jogging, §9.2).
    pub points: Option<crate::geometry::ProfilePoints>,
}

impl PathRun {
    /// Plans the sub-profiles; `par` is the profile's `scPar` snapshot.
    pub fn new(
        geom: PathGeometry,
        start_pose: [f64; 7],
        end_pose: [f64; 7],
        frame_a: Option<MovingFrame>,
        frame_b: Option<MovingFrame>,
        par: &ScPar,
    ) -> Result<Self, String> {
        let mut limits = Vec::new();
        let mut plans = Vec::new();
        let mut s0 = 0.0;
        let single = par.blending_radius > 0.0;
        let whole = effective_limits(par, &geom, 0.0, geom.length, &start_pose, &end_pose);
        for &s1 in &geom.stops {
            let lim = if single {
                whole
            } else {
                effective_limits(par, &geom, s0, s1, &start_pose, &end_pose)
            };
            let p = Profile1::to_position(State1::at_rest(s0), s1, 0.0, &lim)
                .map_err(|e| e.to_string())?;
            limits.push(lim);
            plans.push(p);
            s0 = s1;
        }
        let motion = plans[0];
        Ok(PathRun {
            geom,
            start_pose,
            end_pose,
            frame_a,
            frame_b,
            limits,
            plans,
            sub: 0,
            motion,
            t: 0.0,
            sigma: State1::at_rest(0.0),
            drive: Drive::Run,
            ov: 1.0,
            nominal: true,
            ov_hold: false,
            points: None,
        })
    }

    /// `lrPreCalcProfileTime`: Σ T of the sub-profiles at override 1.
    pub fn precalc_time(&self) -> f64 {
        self.plans.iter().map(|p| p.duration()).sum()
    }

    /// Time from the start (ov = 1) at which σ first reaches `s` (coupling end prediction).
    pub fn time_to_sigma(&self, s: f64) -> f64 {
        let mut t = 0.0;
        for p in &self.plans {
            if p.end().pos >= s - 1e-12 {
                return t + p.time_at_position(s).unwrap_or(p.duration());
            }
            t += p.duration();
        }
        t
    }

    /// Remaining planned time to T at override 1 (valid while the run is nominal).
    pub fn remaining_time(&self) -> f64 {
        if self.drive == Drive::Finished {
            return 0.0;
        }
        let rest: f64 = self
            .plans
            .iter()
            .skip(self.sub + 1)
            .map(|p| p.duration())
            .sum();
        (self.motion.duration() - self.t).max(0.0) + rest
    }

    /// True while the current sub-profile is its original ov = 1 plan.
    pub fn is_nominal(&self) -> bool {
        self.nominal
    }

    fn stop_target(&self) -> f64 {
        self.geom.stops[self.sub]
    }

    fn replan(&mut self) {
        let target = self.stop_target();
        let lim = scaled(&self.limits[self.sub], self.ov);
        match Profile1::to_position(self.sigma, target, 0.0, &lim) {
            Ok(p) => {
                self.motion = p;
                self.t = 0.0;
                self.nominal = false;
            }
            Err(_) => self.drive = Drive::Held,
        }
    }

    /// Applies a new override (§12): scales v, a and j; 0 brings the path to standstill with the
    /// unscaled deceleration and jerk, a later value > 0 continues.
    pub fn set_override(&mut self, ov: f64) {
        if (ov - self.ov).abs() < 1e-12 {
            return;
        }
        self.ov = ov;
        if ov < OV_STANDSTILL {
            if self.drive == Drive::Run {
                let lim = self.limits[self.sub];
                self.brake(&lim);
                self.ov_hold = true;
            }
        } else if self.ov_hold && matches!(self.drive, Drive::Held | Drive::Stopping) {
            self.ov_hold = false;
            self.drive = Drive::Run;
            self.replan();
        } else if self.drive == Drive::Run {
            self.replan();
        }
    }

    /// Starts a path-true stop with deceleration `d` and jerk `j` (§9.1 rule applied by the caller).
    pub fn stop(&mut self, d: f64, j: f64) {
        if matches!(self.drive, Drive::Held | Drive::Finished) {
            return;
        }
        let lim = Limits {
            velocity: self.limits[self.sub]
                .velocity
                .max(self.sigma.vel.abs())
                .max(1e-9),
            acceleration: d,
            deceleration: d,
            jerk: j,
        };
        self.ov_hold = false;
        self.brake(&lim);
    }

    fn brake(&mut self, lim: &Limits) {
        match Profile1::stopping(self.sigma, lim) {
            Ok(p) => {
                self.motion = p;
                self.t = 0.0;
                self.drive = Drive::Stopping;
                self.nominal = false;
            }
            Err(_) => {
                self.sigma = State1::at_rest(self.sigma.pos);
                self.drive = Drive::Held;
            }
        }
    }

    /// Continues a held path from rest: the rest of the sub-profile is re-profiled (§9.2).
    pub fn resume(&mut self) {
        if self.drive == Drive::Finished {
            return;
        }
        self.sigma = State1::at_rest(self.sigma.pos);
        self.drive = Drive::Run;
        self.ov_hold = false;
        if self.ov < OV_STANDSTILL {
            self.ov_hold = true;
            self.drive = Drive::Held;
            return;
        }
        self.replan();
    }

    /// The current progress.
    pub fn cursor(&self) -> Cursor {
        Cursor {
            sub: self.sub,
            motion: self.motion,
            t: self.t,
            sigma: self.sigma,
            drive: self.drive,
            nominal: self.nominal,
            ov_hold: self.ov_hold,
        }
    }

    /// Goes back to a progress taken from this run with [`Self::cursor`].
    pub fn restore(&mut self, c: Cursor) {
        self.sub = c.sub;
        self.motion = c.motion;
        self.t = c.t;
        self.sigma = c.sigma;
        self.drive = c.drive;
        self.nominal = c.nominal;
        self.ov_hold = c.ov_hold;
    }

    /// Advances the path parameter by `dt` (no alloc).
    pub fn advance(&mut self, dt: f64) {
        let mut left = dt;
        loop {
            match self.drive {
                Drive::Held | Drive::Finished => return,
                Drive::Stopping => {
                    self.t += left;
                    self.sigma = self.motion.at(self.t);
                    if self.t >= self.motion.duration() {
                        self.sigma = State1::at_rest(self.sigma.pos);
                        self.drive = Drive::Held;
                    }
                    return;
                }
                Drive::Run => {
                    self.t += left;
                    if self.t < self.motion.duration() {
                        self.sigma = self.motion.at(self.t);
                        return;
                    }
                    // Sub-profile finished: carry the rest of the cycle into the next one.
                    left = self.t - self.motion.duration();
                    self.sigma = State1::at_rest(self.stop_target());
                    if self.sub + 1 >= self.geom.stops.len() {
                        self.drive = Drive::Finished;
                        return;
                    }
                    self.sub += 1;
                    self.t = 0.0;
                    if (self.ov - 1.0).abs() < 1e-12 {
                        self.motion = self.plans[self.sub];
                        self.nominal = true;
                    } else {
                        self.replan();
                    }
                }
            }
        }
    }

    /// True when σ is at rest (held, finished, or not moving).
    pub fn at_rest(&self) -> bool {
        matches!(self.drive, Drive::Held | Drive::Finished)
            || (self.sigma.vel.abs() < 1e-9
                && self.sigma.acc.abs() < 1e-9
                && self.drive != Drive::Run)
    }

    /// Commanded TCP pose at the current σ for belt positions `s_of(belt)` (§15.1).
    pub fn pose(&self, s_of: &dyn Fn(usize) -> f64) -> [f64; 7] {
        let s = self.sigma.pos;
        let g = self.geom.position(s);
        let k = self.geom.coupling(s);
        let da = self
            .frame_a
            .map(|f| f.delta(s_of(f.belt)))
            .unwrap_or_else(Vec3::zeros);
        let db = self
            .frame_b
            .map(|f| f.delta(s_of(f.belt)))
            .unwrap_or_else(Vec3::zeros);
        let p = g + da * (1.0 - k) + db * k;
        let u = PathGeometry::window_fraction(self.geom.orientation_window, s);
        let mut out = [p.x, p.y, p.z, 0.0, 0.0, 0.0, 0.0];
        for q in 3..7 {
            out[q] = self.start_pose[q] + u * (self.end_pose[q] - self.start_pose[q]);
        }
        out
    }

    /// Coupling factor k at the current σ.
    pub fn k(&self) -> f64 {
        self.geom.coupling(self.sigma.pos)
    }

    /// A moving frame currently influences the TCP (belt superposition active).
    pub fn coupled(&self) -> bool {
        let k = self.k();
        (self.frame_a.is_some() && k < 1.0) || (self.frame_b.is_some() && k > 0.0)
    }

    /// Number of profile points passed (`iProfilePointPassed`, §7.10).
    pub fn points_passed(&self) -> i16 {
        let s = self.sigma.pos + 1e-9;
        let a = &self.geom.point_arcs;
        if self.drive == Drive::Finished || s >= a[2] {
            3
        } else if s >= a[1] {
            2
        } else if s >= a[0] {
            1
        } else {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lim(v: f64, a: f64, d: f64, j: f64) -> Limits {
        Limits {
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
        }
    }

    #[test]
    fn closed_form_matches_the_spec_examples() {
        // §19 W1: 0.110 s overhead per sub-profile.
        let l = lim(100.0, 1000.0, 1000.0, 1e5);
        assert!((rest_to_rest_time(50.0, &l) - 0.610).abs() < 1e-9);
        assert!((rest_to_rest_time(211.896, &l) - 2.229).abs() < 1e-3);
        // §19 W5: 4.055 s.
        assert!((rest_to_rest_time(100.0, &lim(25.0, 500.0, 500.0, 1e5)) - 4.055).abs() < 1e-9);
        // W7 braking distance D_ramp(100, 2000) = 3.5.
        assert!((d_ramp(100.0, 2000.0, 1e5) - 3.5).abs() < 1e-12);
        // Triangular ramp (W13): 100·√(100/1e5) = 3.162.
        assert!((d_ramp(100.0, 10000.0, 1e5) - 3.1623).abs() < 1e-4);
    }

    #[test]
    fn profile1_durations_equal_the_closed_form() {
        // Cross-check of the shared generator against §7.7, incl. short moves (no cruise).
        for (len, l) in [
            (50.0, lim(100.0, 1000.0, 1000.0, 1e5)),
            (2.0, lim(100.0, 1000.0, 1000.0, 1e5)),
            (0.01, lim(100.0, 1000.0, 500.0, 1e5)),
            (300.0, lim(50.0, 500.0, 250.0, 1e4)),
        ] {
            let p = Profile1::to_position(State1::at_rest(0.0), len, 0.0, &l).unwrap();
            let t = rest_to_rest_time(len, &l);
            assert!(
                (p.duration() - t).abs() < 1e-6 * t.max(1.0),
                "L {len}: {} vs {t}",
                p.duration()
            );
        }
    }
}
