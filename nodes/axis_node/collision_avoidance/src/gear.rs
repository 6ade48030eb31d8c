//! MC_GearInPosCA (collision_avoidance.md §5.5): coupling state, quintic cam of the Late/Slow
//! strategies, Early tracking in the relative frame; CA outranks the coupling.

use super::*;
/// State of an MC_GearInPosCA coupling (§5.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Gear {
    pub(super) master: usize,
    pub(super) ratio: f64,
    pub(super) msp: f64,
    pub(super) ssp: f64,
    pub(super) strategy: SyncStrategy,
    pub(super) started: bool,
    /// MasterStartDistance (None = start when Active).
    pub(super) start_distance: Option<f64>,
    /// OverrideSlaveDynamicRestrictions: keep the cam when the master velocity changes.
    pub(super) keep_cam: bool,
    /// After-sync limits (§5.5.2, §5.5.4).
    pub(super) after: Dyn,
    /// Has been InSync once (after-sync limits apply from then on).
    pub(super) ever_in_sync: bool,
    pub(super) in_sync: bool,
    pub(super) failed: bool,
    pub(super) cam: Option<Cam>,
    /// Late: planned start point on the master grid and the master velocity it assumes.
    pub(super) late_start: Option<(f64, f64)>,
    /// Restrictions of the sync phase (§5.5.2 options).
    pub(super) limits: SyncLimits,
    /// Coupled target at the end of the current cycle (motor path) \[mm\].
    pub(super) target: f64,
}

/// The sync-phase restrictions of ST_GearInPosCAOptions (§5.5.2); they do not apply once InSync.
/// Positions are in the coupling's coordinate (the offset path with a DynamicsReferenceSystem).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SyncLimits {
    /// MinimalSlavePosition (−inf: none).
    pub(super) min_pos: f64,
    /// NOT DirectionReversalAllowed.
    pub(super) no_reversal: bool,
    /// NOT MasterVelocityUndershootAllowed.
    pub(super) no_undershoot: bool,
    /// NOT MasterVelocityOvershootAllowed.
    pub(super) no_overshoot: bool,
}

/// Master grid of the Late start-point search \[mm\] (§5.5.3).
const LATE_GRID: f64 = 1.0;
/// At most this many grid points are tried (a longer master distance uses a coarser grid,
/// so the search stays bounded).
const LATE_POINTS: f64 = 131_072.0;
/// Cam samples of the feasibility check.
const CAM_SAMPLES: usize = 64;

/// Late (§5.5.3): the largest start point `m_s` on the master grid `MasterSyncPosition − k·1 mm`
/// (k ≥ 1, `m_s ≥ m0`) whose cam from the slave at rest at `x` stays within the sync dynamics
/// and restrictions at master velocity `mv`; else `m0` itself if that is feasible. Latest first,
/// so the first feasible point is the answer. Deterministic and bounded.
#[allow(clippy::too_many_arguments)]
pub(super) fn late_start(
    m0: f64,
    x: f64,
    mv: f64,
    msp: f64,
    ssp: f64,
    r: f64,
    dy: &Dyn,
    lim: &SyncLimits,
) -> Option<f64> {
    let span = msp - m0;
    if !(span > 0.0 && mv > 0.0) {
        return None;
    }
    let grid = LATE_GRID.max(span / LATE_POINTS);
    let rest = State1 {
        pos: x,
        vel: 0.0,
        acc: 0.0,
    };
    let fits =
        |ms: f64| Cam::new(ms, rest, mv, msp, ssp, r).is_some_and(|c| c.feasible(mv, dy, r, lim));
    let mut k = 1.0;
    loop {
        let ms = msp - k * grid;
        if ms < m0 {
            break;
        }
        if fits(ms) {
            return Some(ms);
        }
        k += 1.0;
    }
    fits(m0).then_some(m0)
}

/// Quintic cam `s(m)` over the master position (§5.5.3 Late/Slow): from the slave's state at
/// `m0` to (MasterSyncPosition, SlaveSyncPosition, ratio, 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Cam {
    pub(super) m0: f64,
    pub(super) h: f64,
    pub(super) c: [f64; 6],
    /// Master velocity the cam was planned for \[mm/s\].
    pub(super) mv: f64,
}

impl Cam {
    pub(super) fn new(m0: f64, s: State1, mv: f64, msp: f64, ssp: f64, r: f64) -> Option<Cam> {
        let h = msp - m0;
        if !(h > 1e-9 && mv > 0.0) {
            return None;
        }
        let (c0, c1, c2) = (s.pos, s.vel / mv, s.acc / (mv * mv) / 2.0);
        let d0 = ssp - (c0 + c1 * h + c2 * h * h);
        let d1 = r - (c1 + 2.0 * c2 * h);
        let d2 = -2.0 * c2;
        let c3 = (20.0 * d0 - 8.0 * d1 * h + d2 * h * h) / (2.0 * h.powi(3));
        let c4 = (-30.0 * d0 + 14.0 * d1 * h - 2.0 * d2 * h * h) / (2.0 * h.powi(4));
        let c5 = (12.0 * d0 - 6.0 * d1 * h + d2 * h * h) / (2.0 * h.powi(5));
        Some(Cam {
            m0,
            h,
            c: [c0, c1, c2, c3, c4, c5],
            mv,
        })
    }

    /// s, ds/dm, d²s/dm² at master position `m`.
    pub(super) fn eval(&self, m: f64) -> (f64, f64, f64) {
        let u = (m - self.m0).clamp(0.0, self.h);
        let c = &self.c;
        let p = c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * c[5]))));
        let d1 = c[1] + u * (2.0 * c[2] + u * (3.0 * c[3] + u * (4.0 * c[4] + u * 5.0 * c[5])));
        let d2 = 2.0 * c[2] + u * (6.0 * c[3] + u * (12.0 * c[4] + u * 20.0 * c[5]));
        (p, d1, d2)
    }

    /// Within the sync dynamics and the sync restrictions at a constant master velocity
    /// `mv > 0` (sampled): |v| ≤ V, −D ≤ a ≤ A, |j| ≤ J; position ≥ MinimalSlavePosition; no
    /// reversal against the sync direction; no undershoot (overshoot) of the synchronous
    /// velocity once it has been reached.
    pub(super) fn feasible(&self, mv: f64, dy: &Dyn, r: f64, lim: &SyncLimits) -> bool {
        let c = &self.c;
        let tol = 1.0 + 1e-9;
        let sr = if r < 0.0 { -1.0 } else { 1.0 };
        let (mut reached_low, mut reached_high) = (false, false);
        (0..=CAM_SAMPLES).all(|i| {
            let u = self.h * i as f64 / CAM_SAMPLES as f64;
            let (p, d1, d2) = self.eval(self.m0 + u);
            let d3 = 6.0 * c[3] + u * (24.0 * c[4] + u * 60.0 * c[5]);
            let (v, a, j) = (d1 * mv, d2 * mv * mv, d3 * mv * mv * mv);
            // Slave speed above (> 0) or below (< 0) the synchronous one, per unit of mv.
            let rel = sr * (d1 - r);
            if lim.no_undershoot {
                reached_low |= rel >= -1e-9;
            }
            if lim.no_overshoot {
                reached_high |= rel <= 1e-9;
            }
            v.abs() <= dy.v * tol
                && a <= dy.a * tol
                && -a <= dy.d * tol
                && j.abs() <= dy.j * tol
                && p >= lim.min_pos - EPS
                && !(lim.no_reversal && sr * d1 < -1e-9)
                && !(reached_low && rel < -1e-9)
                && !(reached_high && rel > 1e-9)
        })
    }
}

/// Motor-path state → the coupling's coordinate (offset path `p`, §5.9).
fn to_work(p: Option<geometry::OffsetPath>, s: State1) -> State1 {
    match p {
        None => s,
        Some(p) => {
            let k = p.slope(s.pos);
            State1 {
                pos: p.to_offset(s.pos),
                vel: s.vel * k,
                acc: s.acc * k,
            }
        }
    }
}

/// Inverse of [`to_work`] (velocity steps at curve boundaries are accepted, §5.9).
fn from_work(p: Option<geometry::OffsetPath>, s: State1) -> State1 {
    match p {
        None => s,
        Some(p) => {
            let pos = p.from_offset(s.pos);
            let k = p.slope(pos);
            State1 {
                pos,
                vel: s.vel / k,
                acc: s.acc / k,
            }
        }
    }
}

/// One planner step without a pair constraint in frame `sg` (+1 forward, −1 mirrored).
fn free_step(s: Kin, sg: f64, vmax: f64, dy: &Dyn, target: Option<f64>, dt: f64) -> Kin {
    let o = planner::step(&StepIn {
        s: if sg > 0.0 { s } else { s.mirror() },
        vmax,
        amax: dy.a,
        dmax: dy.d,
        jmax: dy.j,
        target: target.map(|t| t * sg),
        d_ca: dy.d,
        j_ca: dy.j,
        c4: None,
        t: dt,
    });
    if sg > 0.0 {
        o.s
    } else {
        o.s.mirror()
    }
}

/// MinimalSlavePosition (§5.5.2): where a backward-moving state stops with the sync dynamics
/// (the braking the planner's C3 assumes); the position itself otherwise.
fn lowest_reach(e: Kin, dy: &Dyn) -> f64 {
    if e.v < 0.0 || (e.v == 0.0 && e.a < 0.0) {
        let f = e.mirror();
        -planner::stop_point(f, dy.d.max(-f.a), dy.j)
    } else {
        e.x
    }
}

impl CaGroup {
    /// One cycle of an MC_GearInPosCA slave (§5.5.3): the coupled, cam or tracking candidate;
    /// `None` when CA (C4) rejects it (the caller then runs the position planner toward the
    /// coupled target, InSync drops). With a DynamicsReferenceSystem everything but the CA
    /// check runs on the template's offset path.
    pub(super) fn step_gear(
        &mut self,
        k: usize,
        req: Request,
        mut gear: Gear,
        dt: f64,
        axes: &mut [Axis],
    ) -> Option<State1> {
        let ax = self.members[k].axis;
        let path = req.dyn_path;
        let s_motor = axes[ax].set;
        let s = to_work(path, s_motor);
        let ms = axes[gear.master].set;
        let master_updated = self
            .members
            .iter()
            .any(|m| m.axis == gear.master && m.updated);
        // Master at the start and at the end of this cycle (constant acceleration).
        let (m0, mv0, m1, mv1, ma) = if master_updated {
            let mv0 = ms.vel - ms.acc * dt;
            (
                ms.pos - mv0 * dt - ms.acc * dt * dt / 2.0,
                mv0,
                ms.pos,
                ms.vel,
                ms.acc,
            )
        } else {
            let m1 = ms.pos + ms.vel * dt + ms.acc * dt * dt / 2.0;
            (ms.pos, ms.vel, m1, ms.vel + ms.acc * dt, ms.acc)
        };
        let r = gear.ratio;
        let lim = gear.limits;
        let star = |m: f64| gear.ssp + r * (m - gear.msp);
        gear.target = from_work(
            path,
            State1 {
                pos: star(m1),
                vel: 0.0,
                acc: 0.0,
            },
        )
        .pos;
        let coupled = State1 {
            pos: star(m1),
            vel: r * mv1,
            acc: r * ma,
        };
        let dy = if gear.ever_in_sync {
            gear.after
        } else {
            Dyn {
                v: req.dy.v * self.ovr_actual,
                ..req.dy
            }
        };
        // InSync: the coupled law within the after-sync limits, else resync (Early-style).
        if gear.in_sync {
            let a = &gear.after;
            let tol = 1.0 + 1e-9;
            // Velocity with the acceleration ramped out at the after-sync jerk (as C2).
            let v_end = coupled.vel + coupled.acc * coupled.acc.abs() / (2.0 * a.j);
            let within = coupled.vel.abs() <= a.v * tol
                && v_end.abs() <= a.v * tol
                && coupled.acc <= a.a * tol
                && -coupled.acc <= a.d * tol
                && (coupled.acc - s.acc).abs() <= a.j * dt * tol;
            if !within {
                gear.in_sync = false;
                gear.cam = None;
                gear.strategy = SyncStrategy::Early;
            }
        }
        // MasterStartDistance: a standing slave waits until the master passes the start point.
        if let Some(d) = gear.start_distance {
            let start = gear.msp - d;
            let reached = if d > 0.0 { m1 >= start } else { m1 <= start };
            if reached || s.vel != 0.0 || s.acc != 0.0 {
                gear.start_distance = None;
            }
        }
        let cand = if gear.start_distance.is_some() {
            s
        } else if gear.in_sync {
            coupled
        } else {
            let at_rest = s.vel == 0.0 && s.acc == 0.0;
            if !gear.started && gear.cam.is_none() && gear.strategy != SyncStrategy::Early {
                // Late/Slow: a cam over the master position, only toward a master moving
                // to its sync position with the slave at rest; otherwise Early tracking.
                if at_rest && mv0 > 0.0 && m0 < gear.msp {
                    match gear.strategy {
                        SyncStrategy::Slow => match Cam::new(m0, s, mv0, gear.msp, gear.ssp, r) {
                            Some(c) if c.feasible(mv0, &dy, r, &lim) => {
                                gear.cam = Some(c);
                                gear.started = true;
                            }
                            _ => gear.failed = true,
                        },
                        _ => {
                            // Late: the start point on the 1 mm master grid, planned for
                            // the current master velocity (re-planned when it changes).
                            let ms_plan = match gear.late_start {
                                Some((p, v)) if (v - mv0).abs() <= 1e-6 => Some(p),
                                _ => {
                                    let p = late_start(
                                        m0, s.pos, mv0, gear.msp, gear.ssp, r, &dy, &lim,
                                    );
                                    gear.late_start = p.map(|p| (p, mv0));
                                    p
                                }
                            };
                            match ms_plan {
                                None => gear.failed = true,
                                Some(p) if m1 >= p => {
                                    gear.cam = Cam::new(p, s, mv0, gear.msp, gear.ssp, r);
                                    gear.started = gear.cam.is_some();
                                    gear.failed = gear.cam.is_none();
                                }
                                Some(_) => {}
                            }
                        }
                    }
                } else {
                    gear.strategy = SyncStrategy::Early;
                }
            }
            // Late/Slow without OverrideSlaveDynamicRestrictions: a changed master velocity
            // re-plans the cam from the current state; infeasible ⇒ SLAVE_CANNOT_SYNC.
            if let Some(c) = gear.cam {
                if !gear.keep_cam && (mv0 - c.mv).abs() > 1e-6 && m0 < gear.msp && m0 > c.m0 {
                    match Cam::new(m0, s, mv0, gear.msp, gear.ssp, r) {
                        Some(n) if n.feasible(mv0, &dy, r, &lim) => gear.cam = Some(n),
                        _ => gear.failed = true,
                    }
                }
            }
            if gear.failed {
                s
            } else if let Some(c) = gear.cam {
                if m1 >= gear.msp {
                    gear.in_sync = true;
                    coupled
                } else {
                    let (p, d1, d2) = c.eval(m1);
                    State1 {
                        pos: p,
                        vel: d1 * mv1,
                        acc: d2 * mv1 * mv1 + d1 * ma,
                    }
                }
            } else if gear.strategy == SyncStrategy::Early || gear.started {
                gear.started = true;
                early(&mut gear, s, coupled, &dy, (m0, mv0, ma), dt)
            } else {
                s
            }
        };
        gear.ever_in_sync |= gear.in_sync;
        let cand = from_work(path, cand);
        // CA outranks the coupling (§1.10).
        let own_mode = self.mode_of(k);
        let sgc = if cand.vel < 0.0 { -1.0 } else { 1.0 };
        let (b, _, _) = self.c4_bound(k, s_motor, sgc, own_mode, false, dt, axes);
        let m = &mut self.members[k];
        m.d_ca = m.d_ca.max(dy.d.min(m.dynamics.max_d));
        m.j_ca = m.j_ca.max(dy.j);
        let kc = if sgc > 0.0 {
            kin(cand)
        } else {
            kin(cand).mirror()
        };
        let ok = b.is_none_or(|b| planner::c4_ok(&b, kc, m.d_ca, m.j_ca, dt));
        if !ok {
            gear.in_sync = false;
            gear.cam = None;
            gear.strategy = SyncStrategy::Early;
        }
        m.job = Job::Gear { req, gear };
        if !ok {
            return None;
        }
        m.ca_limited = false;
        m.updated = true;
        m.d_b = m.d_ca;
        m.j_b = m.j_ca;
        let dx = cand.pos - s_motor.pos;
        axes[ax].set = cand;
        self.shift(k, dx);
        Some(cand)
    }
}

/// Early (and resync) tracking of `s*(t)` (§5.5.3) in the coupling's coordinate, with the
/// sync restrictions of §5.5.2: jerk-limited tracking in the frame relative to the moving
/// target (feed-forward `ratio·ṁ`); a target faster than the slave may go (or an
/// accelerating master after a loss of sync) is chased in the absolute frame. Returns the
/// candidate state; sets InSync when it reaches the target.
fn early(
    gear: &mut Gear,
    s: State1,
    coupled: State1,
    dy: &Dyn,
    (m0, mv0, ma): (f64, f64, f64),
    dt: f64,
) -> State1 {
    let r = gear.ratio;
    let lim = gear.limits;
    // Sync direction and speed: the restrictions cap the velocity in the travel frame.
    let w = (r * mv0).abs();
    let sigma = if r * mv0 < 0.0 { -1.0 } else { 1.0 };
    let outrun = coupled.vel.abs() >= dy.v * (1.0 - 1e-9);
    let e = if outrun || ((r * ma).abs() > 1e-9 && gear.ever_in_sync) {
        let sga = frame_sign(s, &Job::Idle, 0.0)
            * if coupled.pos < s.pos && s.vel == 0.0 && s.acc == 0.0 {
                -1.0
            } else {
                1.0
            };
        let target = if lim.no_reversal && sga * sigma < 0.0 {
            None
        } else {
            Some(coupled.pos)
        };
        free_step(kin(s), sga, dy.v, dy, target, dt)
    } else {
        let rel = Kin {
            x: s.pos - (gear.ssp + r * (m0 - gear.msp)),
            v: s.vel - r * mv0,
            a: s.acc - r * ma,
        };
        let sgr = if rel.v > 0.0 || (rel.v == 0.0 && (rel.a > 0.0 || (rel.a == 0.0 && rel.x < 0.0)))
        {
            1.0
        } else {
            -1.0
        };
        // In frame sgr the slave's speed in the sync direction is w + sgr·σ·v_frame.
        let orient = sgr * sigma;
        let mut vmax = (dy.v - sgr * r * mv0).max(0.0);
        if (orient > 0.0 && lim.no_overshoot) || (orient < 0.0 && lim.no_undershoot) {
            vmax = 0.0;
        }
        if orient < 0.0 && lim.no_reversal {
            vmax = vmax.min(w);
        }
        // The feed-forward r·m̈ comes on top of the relative acceleration: the relative
        // frame keeps what is left of the limits (an accelerating master, §5.5.3).
        let ff = (r * ma).abs();
        let dyr = Dyn {
            a: (dy.a - ff).max(dy.a * 1e-3),
            d: (dy.d - ff).max(dy.d * 1e-3),
            ..*dy
        };
        let e = free_step(rel, sgr, vmax, &dyr, Some(0.0), dt);
        // InSync also needs the acceleration: taking over the coupled law must not jump by
        // more than one cycle of jerk (an accelerating master, §5.5.3).
        if e.x.abs() <= 1e-3
            && e.v.abs() <= 1e-3
            && (coupled.acc - s.acc).abs() <= dy.j * dt * (1.0 + 1e-9)
        {
            gear.in_sync = true;
            return coupled;
        }
        Kin {
            x: coupled.pos + e.x,
            v: coupled.vel + e.v,
            a: coupled.acc + e.a,
        }
    };
    // MinimalSlavePosition: a candidate that could no longer stop above it is replaced by
    // the approach to it (the planner's C3 keeps it from there on, §8.5).
    let e = if lowest_reach(e, dy) < lim.min_pos - EPS {
        let ks = kin(s);
        if ks.v > 0.0 || (ks.v == 0.0 && ks.a > 0.0) {
            free_step(ks, 1.0, dy.v, dy, None, dt)
        } else {
            free_step(ks, -1.0, dy.v, dy, Some(lim.min_pos.min(s.pos)), dt)
        }
    } else {
        e
    };
    State1 {
        pos: e.x,
        vel: e.v,
        acc: e.a,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FREE: SyncLimits = SyncLimits {
        min_pos: f64::NEG_INFINITY,
        no_reversal: false,
        no_undershoot: false,
        no_overshoot: false,
    };

    #[test]
    fn late_start_is_the_largest_feasible_point_of_the_1_mm_grid() {
        // §10.9: master at 0 cruising at 500, sync at 1000; slave at rest at 0, s* = m + 400.
        let dy = Dyn {
            v: 1500.0,
            a: 10000.0,
            d: 10000.0,
            j: 100000.0,
        };
        let ms = late_start(0.0, 0.0, 500.0, 1000.0, 1400.0, 1.0, &dy, &FREE).unwrap();
        assert_eq!(ms, (ms - 1000.0).round() + 1000.0, "on the grid: {ms}");
        assert!(ms > 0.0 && ms < 1000.0);
        let rest = State1 {
            pos: 0.0,
            vel: 0.0,
            acc: 0.0,
        };
        let fits = |m: f64| {
            Cam::new(m, rest, 500.0, 1000.0, 1400.0, 1.0)
                .is_some_and(|c| c.feasible(500.0, &dy, 1.0, &FREE))
        };
        assert!(fits(ms));
        for k in 1..=((1000.0 - ms) as usize - 1) {
            assert!(
                !fits(1000.0 - k as f64),
                "{} is later and feasible",
                1000.0 - k as f64
            );
        }
        // Nothing feasible from here on ⇒ None (SLAVE_CANNOT_SYNC).
        assert_eq!(
            late_start(990.0, 0.0, 500.0, 1000.0, 1400.0, 1.0, &dy, &FREE),
            None
        );
        // Bounded: a 10 km master distance is searched on a coarser grid.
        let far = late_start(-1e7, 0.0, 500.0, 1000.0, 1400.0, 1.0, &dy, &FREE).unwrap();
        assert!(far < 1000.0 && far > -1e7);
    }
}
