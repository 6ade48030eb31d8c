//! MC_Jog (§4.11): jog buttons, standard and inching modes.

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ MC_Jog (§4.11)

    /// MC_Jog (§4.11).
    pub fn jog(&mut self, ax: usize, c: Jog) -> Result<FbReply, Rejection> {
        let fb = "MC_Jog";
        let a = &self.axes[ax];
        let name = a.name.clone();
        finite(&name, fb, "Position", c.position)?;
        if !c.jog_forward && !c.jog_backwards {
            return Err(reject(
                ErrorId::VALUE_OUT_OF_RANGE,
                format!("axis '{name}': {fb}: neither JogForward nor JogBackwards is TRUE (no rising edge)"),
            ));
        }
        let dir = if c.jog_forward { 1.0 } else { -1.0 };
        let standard = |v: f64| Limits {
            velocity: v,
            acceleration: a.cfg.acceleration,
            deceleration: a.cfg.deceleration,
            jerk: a.cfg.jerk,
        };
        let (req, limits) = match c.mode {
            JogMode::StandardSlow => (
                Request::Velocity(Direction::Positive),
                standard(a.cfg.manual_velocity_slow.min(a.cfg.max_velocity)),
            ),
            JogMode::StandardFast => (
                Request::Velocity(Direction::Positive),
                standard(a.cfg.manual_velocity_fast.min(a.cfg.max_velocity)),
            ),
            JogMode::Continous => {
                let l = move_limits(
                    a,
                    fb,
                    Some(c.velocity),
                    c.acceleration,
                    c.deceleration,
                    c.jerk,
                )?;
                (Request::Velocity(Direction::Positive), l)
            }
            JogMode::Inching | JogMode::InchingModulo => {
                let l = move_limits(
                    a,
                    fb,
                    Some(c.velocity),
                    c.acceleration,
                    c.deceleration,
                    c.jerk,
                )?;
                if c.position <= 0.0 {
                    return Err(not_correct(
                        &name,
                        fb,
                        "Position",
                        c.position,
                        "must be > 0 for the INCHING modes",
                    ));
                }
                let req = if c.mode == JogMode::Inching {
                    Request::Relative(dir * c.position)
                } else {
                    // Snap to the next multiple of Position strictly beyond SetPos (§4.11).
                    let p = c.position;
                    let s = a.set.pos;
                    let t = if dir > 0.0 {
                        ((s + 1e-9) / p).floor() * p + p
                    } else {
                        ((s - 1e-9) / p).ceil() * p - p
                    };
                    Request::Absolute(t)
                };
                (req, l)
            }
        };
        let req = match req {
            Request::Velocity(_) => Request::Velocity(if dir > 0.0 {
                Direction::Positive
            } else {
                Direction::Negative
            }),
            r => r,
        };
        let opts = MoveOptions {
            ignore_position_monitoring: true,
            ..Default::default()
        };
        self.motion(ax, FbKind::Jog, fb, req, limits, BufferMode::Aborting, opts)
    }
}
