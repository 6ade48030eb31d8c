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
    /// Coupled target at the end of the current cycle \[mm\].
    pub(super) target: f64,
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

    /// Within the sync dynamics at a constant master velocity `mv` (33 samples).
    pub(super) fn feasible(&self, mv: f64, dy: &Dyn) -> bool {
        let c = &self.c;
        let tol = 1.0 + 1e-9;
        (0..=32).all(|i| {
            let u = self.h * i as f64 / 32.0;
            let (_, d1, d2) = self.eval(self.m0 + u);
            let d3 = 6.0 * c[3] + u * (24.0 * c[4] + u * 60.0 * c[5]);
            let (v, a, j) = (d1 * mv, d2 * mv * mv, d3 * mv * mv * mv);
            v.abs() <= dy.v * tol && a <= dy.a * tol && -a <= dy.d * tol && j.abs() <= dy.j * tol
        })
    }
}

impl CaGroup {
    /// One cycle of an MC_GearInPosCA slave (§5.5.3): the coupled, cam or tracking candidate;
    /// `None` when CA (C4) rejects it (the caller then runs the position planner toward the
    /// coupled target, InSync drops).
    pub(super) fn step_gear(
        &mut self,
        k: usize,
        req: Request,
        mut gear: Gear,
        dt: f64,
        axes: &mut [Axis],
    ) -> Option<State1> {
        let ax = self.members[k].axis;
        let s = axes[ax].set;
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
        let star = |m: f64| gear.ssp + r * (m - gear.msp);
        gear.target = star(m1);
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
            if !gear.started && gear.cam.is_none() && gear.strategy != SyncStrategy::Early {
                // Late/Slow: a cam over the master position, only toward a master moving
                // to its sync position with the slave at rest; otherwise Early tracking.
                let at_rest = s.vel == 0.0 && s.acc == 0.0;
                let cam = Cam::new(m0, s, mv0, gear.msp, gear.ssp, r);
                match cam {
                    Some(c) if at_rest && mv0 > 0.0 => {
                        let now_ok = c.feasible(mv0, &dy);
                        let start = match gear.strategy {
                            SyncStrategy::Slow => true,
                            _ => {
                                // Late: start when waiting one more cycle becomes infeasible.
                                let next = Cam::new(m1, s, mv0, gear.msp, gear.ssp, r);
                                !next.is_some_and(|n| n.feasible(mv0, &dy))
                            }
                        };
                        if start {
                            if now_ok {
                                gear.cam = Some(c);
                                gear.started = true;
                            } else {
                                gear.failed = true;
                            }
                        }
                    }
                    _ => gear.strategy = SyncStrategy::Early,
                }
            }
            // Late/Slow without OverrideSlaveDynamicRestrictions: a changed master velocity
            // re-plans the cam from the current state; infeasible ⇒ SLAVE_CANNOT_SYNC.
            if let Some(c) = gear.cam {
                if !gear.keep_cam && (mv0 - c.mv).abs() > 1e-6 && m0 < gear.msp {
                    match Cam::new(m0, s, mv0, gear.msp, gear.ssp, r) {
                        Some(n) if n.feasible(mv0, &dy) => gear.cam = Some(n),
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
                // Early: jerk-limited tracking of s*(t) in the relative frame; a target
                // faster than the slave may go (or an accelerating master after a loss of
                // sync) is chased in the absolute frame within the slave's limits.
                let outrun = (r * mv1).abs() >= dy.v * (1.0 - 1e-9);
                if outrun || ((r * ma).abs() > 1e-9 && gear.ever_in_sync) {
                    let sga = frame_sign(s, &Job::Idle, 0.0)
                        * if coupled.pos < s.pos && s.vel == 0.0 && s.acc == 0.0 {
                            -1.0
                        } else {
                            1.0
                        };
                    let o = planner::step(&StepIn {
                        s: if sga > 0.0 { kin(s) } else { kin(s).mirror() },
                        vmax: dy.v,
                        amax: dy.a,
                        dmax: dy.d,
                        jmax: dy.j,
                        target: Some(coupled.pos * sga),
                        d_ca: dy.d,
                        j_ca: dy.j,
                        c4: None,
                        t: dt,
                    });
                    let e = if sga > 0.0 { o.s } else { o.s.mirror() };
                    State1 {
                        pos: e.x,
                        vel: e.v,
                        acc: e.a,
                    }
                } else {
                    let rel = Kin {
                        x: s.pos - star(m0),
                        v: s.vel - r * mv0,
                        a: s.acc - r * ma,
                    };
                    let sgr = if rel.v > 0.0
                        || (rel.v == 0.0 && (rel.a > 0.0 || (rel.a == 0.0 && rel.x < 0.0)))
                    {
                        1.0
                    } else {
                        -1.0
                    };
                    let vmax = (dy.v - sgr * r * mv0).max(0.0);
                    let o = planner::step(&StepIn {
                        s: if sgr > 0.0 { rel } else { rel.mirror() },
                        vmax,
                        amax: dy.a,
                        dmax: dy.d,
                        jmax: dy.j,
                        target: Some(0.0),
                        d_ca: dy.d,
                        j_ca: dy.j,
                        c4: None,
                        t: dt,
                    });
                    let e = if sgr > 0.0 { o.s } else { o.s.mirror() };
                    if e.x.abs() <= 1e-3 && e.v.abs() <= 1e-3 {
                        gear.in_sync = true;
                        coupled
                    } else {
                        State1 {
                            pos: coupled.pos + e.x,
                            vel: coupled.vel + e.v,
                            acc: coupled.acc + e.a,
                        }
                    }
                }
            } else {
                s
            }
        };
        gear.ever_in_sync |= gear.in_sync;
        // CA outranks the coupling (§1.10).
        let own_mode = self.mode_of(k);
        let sgc = if cand.vel < 0.0 { -1.0 } else { 1.0 };
        let (b, _) = self.c4_bound(k, s, sgc, own_mode, false, dt, axes);
        let m = &mut self.members[k];
        m.d_ca = m.d_ca.max(dy.d.min(m.dynamics.max_d));
        m.j_ca = m.j_ca.max(dy.j);
        let kc = if sgc > 0.0 {
            kin(cand)
        } else {
            kin(cand).mirror()
        };
        let ok = b.is_none_or(|b| planner::c4_ok(&b, kc, m.d_ca, m.j_ca));
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
        let dx = cand.pos - s.pos;
        axes[ax].set = cand;
        self.shift(k, dx);
        Some(cand)
    }
}
