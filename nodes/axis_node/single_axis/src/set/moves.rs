//! The motion FBs (§4.8): MC_MoveAbsolute/Relative/Additive/Modulo/Velocity, the continuous
//! moves, MC_Halt and MC_Stop, with their BufferMode handling.

use super::*;

/// A move FB: its dynamics screened (§3.5), then admitted through the buffer logic (§3.6).
macro_rules! positioning {
    ($s:ident, $ax:expr, $c:expr, $kind:ident, $req:expr) => {{
        let fb = concat!("MC_", stringify!($kind));
        let l = move_limits(
            &$s.axes[$ax],
            fb,
            Some($c.velocity),
            $c.acceleration,
            $c.deceleration,
            $c.jerk,
        )?;
        $s.motion($ax, FbKind::$kind, fb, $req, l, $c.buffer_mode, $c.options)
    }};
}

impl AxisSet {
    // ------------------------------------------------------------------ the FB calls

    /// MC_MoveAbsolute (§4.8.1).
    pub fn move_absolute(&mut self, ax: usize, c: MoveAbsolute) -> Result<FbReply, Rejection> {
        finite(&c.axis, "MC_MoveAbsolute", "Position", c.position)?;
        positioning!(self, ax, c, MoveAbsolute, Request::Absolute(c.position))
    }

    /// MC_MoveRelative (§4.8.2).
    pub fn move_relative(&mut self, ax: usize, c: MoveRelative) -> Result<FbReply, Rejection> {
        finite(&c.axis, "MC_MoveRelative", "Distance", c.distance)?;
        positioning!(self, ax, c, MoveRelative, Request::Relative(c.distance))
    }

    /// MC_MoveAdditive (§4.8.3).
    pub fn move_additive(&mut self, ax: usize, c: MoveAdditive) -> Result<FbReply, Rejection> {
        finite(&c.axis, "MC_MoveAdditive", "Distance", c.distance)?;
        positioning!(self, ax, c, MoveAdditive, Request::Additive(c.distance))
    }

    /// MC_MoveModulo (§4.8.4).
    pub fn move_modulo(&mut self, ax: usize, c: MoveModulo) -> Result<FbReply, Rejection> {
        finite(&c.axis, "MC_MoveModulo", "Position", c.position)?;
        let req = Request::Modulo {
            position: c.position,
            direction: c.direction,
        };
        positioning!(self, ax, c, MoveModulo, req)
    }

    /// MC_MoveVelocity (§4.8.6).
    pub fn move_velocity(&mut self, ax: usize, c: MoveVelocity) -> Result<FbReply, Rejection> {
        positioning!(self, ax, c, MoveVelocity, Request::Velocity(c.direction))
    }

    /// MC_MoveContinuousAbsolute (§4.8.7).
    pub fn move_continuous_absolute(
        &mut self,
        ax: usize,
        c: MoveContinuousAbsolute,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_MoveContinuousAbsolute";
        finite(&c.axis, fb, "Position", c.position)?;
        let ev = end_velocity(&self.axes[ax], fb, c.end_velocity)?;
        let req = Request::ContinuousAbsolute(c.position, ev);
        positioning!(self, ax, c, MoveContinuousAbsolute, req)
    }

    /// MC_MoveContinuousRelative (§4.8.8).
    pub fn move_continuous_relative(
        &mut self,
        ax: usize,
        c: MoveContinuousRelative,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_MoveContinuousRelative";
        finite(&c.axis, fb, "Distance", c.distance)?;
        let ev = end_velocity(&self.axes[ax], fb, c.end_velocity)?;
        let req = Request::ContinuousRelative(c.distance, ev);
        positioning!(self, ax, c, MoveContinuousRelative, req)
    }

    /// MC_Halt (§4.8.9).
    pub fn halt(&mut self, ax: usize, c: Halt) -> Result<FbReply, Rejection> {
        let l = self.halt_limits(ax, "MC_Halt", c.deceleration, c.jerk)?;
        let (mode, options) = (c.buffer_mode, c.options);
        self.motion(ax, FbKind::Halt, "MC_Halt", Request::Halt, l, mode, options)
    }

    // ------------------------------------------------------------------ motion FBs

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn motion(
        &mut self,
        ax: usize,
        kind: FbKind,
        fb: &str,
        req: Request,
        limits: Limits,
        mode: BufferMode,
        options: MoveOptions,
    ) -> Result<FbReply, Rejection> {
        let class = match req {
            Request::Velocity(_)
            | Request::ContinuousAbsolute(..)
            | Request::ContinuousRelative(..) => FbClass::MoveContinuous,
            Request::Halt => FbClass::Halt,
            _ => FbClass::MoveDiscrete,
        };
        let decouple = self.admit_motion(ax, class, fb, mode)?;
        let a = &self.axes[ax];
        let name = a.name.clone();
        if options.enable_blending_position {
            finite(
                &name,
                fb,
                "Options.BlendingPosition",
                options.blending_position,
            )?;
        }
        // Is the axis executing another command (BufferMode is evaluated only then)?
        let running = a.job.filter(|j| {
            j.owner.is_some()
                && matches!(
                    j.kind,
                    JobKind::Position | JobKind::Velocity | JobKind::Halt
                )
        });
        let settling = a.settle.is_some();
        let mut buffered = mode != BufferMode::Aborting && (running.is_some() || settling);
        // Endless motions have no end: buffered acts like aborting unless a blending position
        // is given (rule 3/6).
        let mut blend_at: Option<f64> = None;
        if let Some(j) = running {
            if buffered {
                let dir1 = travel_dir(a, &j);
                // Behind a running MC_Halt the follow-up starts at rest (no blending point).
                if options.enable_blending_position && j.kind != JobKind::Halt {
                    let bp = options.blending_position;
                    if j.kind == JobKind::Position {
                        let p1 = j.target + j.offset;
                        if (p1 - bp) * dir1 < 0.0 {
                            return Err(reject(
                                BLENDING_POSITION_INVALID,
                                format!("axis '{name}': {fb}: BlendingPosition {bp} lies beyond the end position {p1} of the running command"),
                            ));
                        }
                    }
                    if (bp - a.set.pos) * dir1 < 0.0 {
                        buffered = false; // already passed: at once (like Aborting)
                    } else {
                        blend_at = Some(bp);
                    }
                } else if j.kind == JobKind::Velocity {
                    buffered = false;
                }
            }
        }
        if buffered && a.pending.is_some() {
            return Err(reject(
                BUFFER_FULL,
                format!("axis '{name}': {fb}: a command is already buffered (Buffer Full)"),
            ));
        }
        // MC_MoveModulo against the current travel direction: the FB ends with Error 0x4B04
        // and the axis is stopped safely (manual, §4.8.4) - an execution error, not a
        // rejection.
        if let Request::Modulo {
            position,
            direction,
        } = req
        {
            let v = a.set.vel;
            let wanted = match direction {
                Direction::Positive => 1.0,
                Direction::Negative => -1.0,
                _ => 0.0,
            };
            if !buffered && position >= 0.0 && v.abs() > 1e-9 && wanted * v < 0.0 {
                let id = self.fbs.admit(ax, kind, CommandState::Active);
                let a = &mut self.axes[ax];
                let fbs = &mut self.fbs;
                a.cmd_no = a.cmd_no.wrapping_add(1);
                a.abort_motion(fbs);
                let profile = a.plan_stop(&limits);
                let stop = profile.end().pos;
                a.start_job(Job::internal(JobKind::Halt, profile, stop, limits));
                a.last_target = Some(stop);
                fbs.error(id, INVALID_MODE);
                return Ok(Self::reply(id));
            }
        }
        // The set position at which the command will take over.
        let base = match (buffered, running) {
            (true, Some(j)) => blend_at.unwrap_or(j.target + j.offset),
            _ => a.set.pos,
        };
        let last_target = if buffered {
            Some(base)
        } else {
            a.last_target
                .filter(|_| !running.is_some_and(|j| j.kind == JobKind::Velocity))
        };
        let spec = match req {
            Request::Absolute(p) => Spec::Position {
                target: p,
                limits,
                monitor: !options.ignore_position_monitoring,
            },
            Request::Relative(d) => Spec::Position {
                target: base + d,
                limits,
                monitor: !options.ignore_position_monitoring,
            },
            Request::Additive(d) => Spec::Position {
                target: last_target.unwrap_or(base) + d,
                limits,
                monitor: !options.ignore_position_monitoring,
            },
            Request::Modulo {
                position,
                direction,
            } => {
                let target =
                    modulo_target(a, &name, fb, position, direction, &limits, buffered, base)?;
                Spec::Position {
                    target,
                    limits,
                    monitor: !options.ignore_position_monitoring,
                }
            }
            Request::ContinuousAbsolute(p, ev) => Spec::Continuous {
                target: p,
                end_velocity: ev,
                limits,
            },
            Request::ContinuousRelative(d, ev) => Spec::Continuous {
                target: base + d,
                end_velocity: ev,
                limits,
            },
            Request::Velocity(direction) => {
                let dir = match direction {
                    Direction::Positive => 1.0,
                    Direction::Negative => -1.0,
                    Direction::Current if a.set.vel.abs() > 1e-9 => a.set.vel.signum(),
                    d => {
                        return Err(reject(
                            COMMAND_NOT_PERMITTED,
                            format!(
                                "axis '{name}': {fb}: Direction {d:?} gives no direction of motion"
                            ),
                        ))
                    }
                };
                Spec::Velocity { dir, limits }
            }
            Request::Halt => Spec::Halt {
                limits,
                monitor: options.enable_stop_position_monitoring,
            },
        };
        // A profile may move the target of a discrete motion started while moving (ISG:
        // R-SYS-2 on modulo axes).
        let spec = match spec {
            Spec::Position {
                target,
                limits,
                monitor,
            } if !buffered && matches!(req, Request::Absolute(_) | Request::Relative(_)) => {
                Spec::Position {
                    target: self
                        .profile
                        .target_while_moving(ax, &self.axes[ax], target, &limits),
                    limits,
                    monitor,
                }
            }
            s => s,
        };
        let a = &self.axes[ax];
        // Software limits (§1.3) and feed enables (§2.4).
        if let Spec::Position { target, .. } | Spec::Continuous { target, .. } = spec {
            if !target.is_finite() {
                return Err(reject(
                    ErrorId::NOT_FINITE,
                    format!("axis '{name}': {fb}: target {target} is not finite"),
                ));
            }
            if a.soft_limit(1.0).is_some_and(|l| target > l)
                || a.soft_limit(-1.0).is_some_and(|l| target < l)
            {
                return Err(reject(
                    SOFT_LIMIT_TARGET,
                    format!(
                        "axis '{name}': {fb}: target {target} outside the software limits [{}, {}]",
                        a.cfg.min_soft_pos_limit, a.cfg.max_soft_pos_limit
                    ),
                ));
            }
        }
        let start_dir = match spec {
            Spec::Position { target, .. } | Spec::Continuous { target, .. } => {
                (target - base).signum() * ((target - base).abs() > 1e-12) as i32 as f64
            }
            Spec::Velocity { dir, .. } => dir,
            Spec::Halt { .. } => 0.0,
        };
        if (start_dir > 0.0 && !a.enable_positive) || (start_dir < 0.0 && !a.enable_negative) {
            return Err(reject(
                AXIS_CANNOT_BE_STARTED,
                format!(
                    "axis '{name}': {fb}: feed enable for the {} direction is missing",
                    if start_dir > 0.0 {
                        "positive"
                    } else {
                        "negative"
                    }
                ),
            ));
        }

        // Admitted.
        if decouple {
            self.axes[ax].decouple_keep_velocity();
        }
        let id = self.fbs.admit(
            ax,
            kind,
            if buffered {
                CommandState::Busy
            } else {
                CommandState::Active
            },
        );
        let a = &mut self.axes[ax];
        let fbs = &mut self.fbs;
        a.cmd_no = a.cmd_no.wrapping_add(1);
        if !matches!(spec, Spec::Halt { .. }) {
            a.last_dec = limits.deceleration;
            a.last_jerk = limits.jerk;
        }
        if !buffered {
            a.abort_motion(fbs);
            if let Some(r) = a.reset_waiting.take() {
                fbs.done(r);
            }
            if !a.start_spec(id, spec, fbs) {
                fbs.error(id, PARAMETER_NOT_CORRECT);
            }
            return Ok(Self::reply(id));
        }
        let pending = Pending { owner: id, spec };
        match running {
            None => {
                // Settling after the end of the previous move: it is complete, start now.
                if let Some(s) = a.settle.take() {
                    fbs.done(s.owner);
                }
                a.take_over(pending, fbs);
            }
            Some(j) => {
                blend(a, j, pending, mode, blend_at);
            }
        }
        Ok(Self::reply(id))
    }

    pub(crate) fn halt_limits(
        &self,
        ax: usize,
        fb: &str,
        dec: f64,
        jerk: f64,
    ) -> Result<Limits, Rejection> {
        let a = &self.axes[ax];
        finite(&a.name, fb, "Deceleration", dec)?;
        finite(&a.name, fb, "Jerk", jerk)?;
        // ≤ 0 → last move's values; never weaker than the active command (§4.8.9).
        let mut d = if dec > 0.0 { dec } else { a.last_dec };
        let mut j = if jerk > 0.0 { jerk } else { a.last_jerk };
        if let Some(job) = a.job {
            d = d.max(job.limits.deceleration);
            j = j.max(job.limits.jerk);
        }
        Ok(Limits {
            velocity: a.cfg.max_velocity,
            acceleration: a.cfg.acceleration.max(d),
            deceleration: d,
            jerk: j,
        })
    }

    /// MC_Stop (§4.8.10).
    pub fn stop(&mut self, ax: usize, c: Stop) -> Result<FbReply, Rejection> {
        let limits = self.halt_limits(ax, "MC_Stop", c.deceleration, c.jerk)?;
        if self.admit_motion(ax, FbClass::Stop, "MC_Stop", BufferMode::Aborting)? {
            self.axes[ax].decouple_keep_velocity();
        }
        let id = self.fbs.admit(ax, FbKind::Stop, CommandState::Active);
        let a = &mut self.axes[ax];
        let fbs = &mut self.fbs;
        a.cmd_no = a.cmd_no.wrapping_add(1);
        if let Some(old) = a.lock.take() {
            fbs.aborted(old.owner);
            if let Some(i) = fbs.get_mut(old.owner) {
                i.locked = false;
            }
        }
        a.abort_motion(fbs);
        if let Some(r) = a.reset_waiting.take() {
            fbs.done(r);
        }
        let profile = a.plan_stop(&limits);
        let stop = profile.end().pos;
        a.start_job(Job {
            owner: Some(id),
            ..Job::internal(JobKind::Stop, profile, stop, limits)
        });
        let monitor =
            c.options.enable_stop_position_monitoring && a.cfg.en_target_position_monitoring;
        a.lock = Some(Lock {
            owner: id,
            execute: true,
            at_rest: false,
            monitor,
            done: false,
            unlock_in: 2,
        });
        a.has_been_stopped = true;
        a.last_target = Some(stop);
        Ok(Self::reply(id))
    }
}
