//! The `motion_core::Engine` implementation: command admission and screening (§18).

use super::*;

impl Engine for PickPlaceEngine {
    type Command = PickPlaceCommand;
    type Reply = CmdId;
    type Snapshot = PickPlaceSnapshot;

    /// `xPathStop` (§9): the group stops on its path with the path deceleration.
    fn fail_safe_stop(&mut self) {
        let _ = self.command(PickPlaceCommand::SetStopInputs(StopInputs {
            path_stop: Some(true),
            ..StopInputs::default()
        }));
    }

    fn at_rest(&self) -> bool {
        self.standstill()
    }

    fn command(&mut self, cmd: PickPlaceCommand) -> Result<CmdId, Rejection> {
        use PickPlaceCommand as C;
        // Internal Control (§3.1 proposal): only the HMI drives the TM; xStopALL always acts.
        match &cmd {
            C::HmiSetInternalControl(on) => {
                if *on && !self.inputs.enable_internal_control {
                    return Err(Rejection::new(ids::COMMAND_NOT_ALLOWED, "pickplace: internal control requested while xEnableInternalControl = FALSE"));
                }
                self.internal_control = *on;
                return Ok(self.new_id());
            }
            C::Hmi(inner) => {
                if !self.internal_control {
                    return Err(Rejection::new(
                        ids::COMMAND_NOT_ALLOWED,
                        "pickplace: HMI command while internal control is not active",
                    ));
                }
                if matches!(**inner, C::Hmi(_) | C::HmiSetInternalControl(_)) {
                    return Err(Rejection::new(
                        ids::COMMAND_NOT_ALLOWED,
                        "pickplace: nested HMI command",
                    ));
                }
                let inner = (**inner).clone();
                return self.apply(inner);
            }
            C::SetStopInputs(StopInputs {
                stop_all: Some(v), ..
            }) if self.internal_control => {
                self.inputs.stop_all = *v;
                return Ok(self.new_id());
            }
            C::SetEnableInternalControl(_)
            | C::SimSetBeltVelocity { .. }
            | C::SimSetDigitalInputs { .. }
            | C::SimInjectFault { .. } => {}
            _ if self.internal_control => {
                return Err(Rejection::new(
                    ids::COMMAND_NOT_ALLOWED,
                    "pickplace: internal control active; only ~/hmi and xStopALL are accepted",
                ));
            }
            _ => {}
        }
        self.apply(cmd)
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        self.step_cycle(tick, events);
    }

    fn snapshot(&self) -> PickPlaceSnapshot {
        self.make_snapshot()
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        // A resume edge's id stands for the held profile it resumed.
        let id = self
            .resume_ids
            .iter()
            .find(|&&(_, resume)| resume == id)
            .map_or(id, |&(held, _)| held);
        // §18: cancel = xPathHalt pulse-and-release + xAbort at standstill, done here without
        // touching the FB's level inputs. A queued or preparing profile is simply dropped.
        let before = self.queue.len();
        self.queue.retain(|j| j.id != Some(id));
        if self.queue.len() != before {
            self.deferred_events.push(CommandEvent {
                id,
                state: CommandState::Aborted,
            });
            return Ok(());
        }
        if self
            .append_prep
            .as_ref()
            .is_some_and(|(_, j)| j.id == Some(id))
        {
            self.append_prep = None;
            self.deferred_events.push(CommandEvent {
                id,
                state: CommandState::Aborted,
            });
            return Ok(());
        }
        let running = self
            .running
            .as_deref()
            .is_some_and(|r| r.job.id == Some(id));
        let preparing = matches!(&self.prep, Some((_, Prep::New(j))) if j.id == Some(id));
        if running || preparing {
            self.cancel_request = Some(id);
        }
        Ok(())
    }
}

impl PickPlaceEngine {
    /// Applies one (admitted) command to the inputs.
    pub(super) fn apply(&mut self, cmd: PickPlaceCommand) -> Result<CmdId, Rejection> {
        let id = self.new_id();
        match cmd {
            PickPlaceCommand::HmiSetInternalControl(_) | PickPlaceCommand::Hmi(_) => {}
            PickPlaceCommand::SetEnable(v) => self.inputs.enable = v,
            PickPlaceCommand::SetRegulatorOn(v) => self.inputs.regulator_on_all = v,
            PickPlaceCommand::SetEnableInternalControl(v) => {
                if !v {
                    self.internal_control = false;
                }
                self.inputs.enable_internal_control = v
            }
            PickPlaceCommand::ResetError => self.pulses.push_back(Pulse {
                kind: PulseKind::ResetError,
                id: Some(id),
                set_target: 0,
            }),
            PickPlaceCommand::SetStopInputs(StopInputs {
                path_stop,
                path_halt,
                stop_all,
                path_interrupt,
            }) => {
                if let Some(v) = path_stop {
                    self.inputs.path_stop = v;
                }
                if let Some(v) = path_halt {
                    self.inputs.path_halt = v;
                }
                if let Some(v) = stop_all {
                    self.inputs.stop_all = v;
                }
                if let Some(v) = path_interrupt {
                    self.inputs.path_interrupt = v;
                }
            }
            PickPlaceCommand::SetOverride(v) => {
                Self::finite("lrOverride", v)?;
                self.inputs.override_ = v;
            }
            PickPlaceCommand::Jog {
                select_axis,
                jog_pos,
                jog_neg,
            } => {
                if select_axis > 13 {
                    return Err(Rejection::new(
                        ErrorId::ENUM_OUT_OF_RANGE,
                        format!("pickplace: eSelectAxis = {select_axis} is not 0 … 13"),
                    ));
                }
                // eSelectAxis is latched at the jog start; changes outside READY have no effect.
                self.inputs.select_axis = select_axis;
                self.inputs.jog_pos = jog_pos;
                self.inputs.jog_neg = jog_neg;
            }
            PickPlaceCommand::Execute { set_target } => {
                self.pulses.push_back(Pulse {
                    kind: PulseKind::Execute,
                    id: Some(id),
                    set_target,
                });
            }
            PickPlaceCommand::Abort => self.pulses.push_back(Pulse {
                kind: PulseKind::Abort,
                id: Some(id),
                set_target: 0,
            }),
            PickPlaceCommand::AckGripper => self.pulses.push_back(Pulse {
                kind: PulseKind::AckGripper,
                id: Some(id),
                set_target: 0,
            }),
            PickPlaceCommand::GroupHome => self.pulses.push_back(Pulse {
                kind: PulseKind::GroupHome,
                id: Some(id),
                set_target: 0,
            }),
            PickPlaceCommand::SetParams(p) => {
                p.validate()?;
                self.par = *p;
            }
            PickPlaceCommand::SetBeltParams { belt, params } => {
                let n = Self::belt_checked(belt)?;
                params.validate(n)?;
                self.belts[n - 1].par = params;
            }
            PickPlaceCommand::BeltInput {
                belt,
                receive,
                valid_pos,
                initial_object_position,
                aux1_target_pos,
            } => {
                let n = Self::belt_checked(belt)?;
                for (i, v) in initial_object_position.iter().enumerate() {
                    Self::finite(
                        &format!("ascBeltInput[{n}].ascInitialObjectPosition[{}]", i + 1),
                        *v,
                    )?;
                }
                Self::finite(
                    &format!("ascBeltInput[{n}].lrAux1TargetPos"),
                    aux1_target_pos,
                )?;
                let b = &mut self.belts[n - 1];
                b.receive = receive;
                b.valid_pos = valid_pos;
                b.initial_object_position = initial_object_position;
                b.aux1_target_pos = aux1_target_pos;
            }
            PickPlaceCommand::DetectWorkpiece {
                belt,
                position,
                valid_delay_cycles,
            } => {
                let n = Self::belt_checked(belt)?;
                for (i, v) in position.iter().enumerate() {
                    Self::finite(&format!("detect_workpiece.position[{i}]"), *v)?;
                }
                self.sim_detect[n - 1].push_back(SimDetect {
                    position,
                    delay: valid_delay_cycles,
                });
            }
            PickPlaceCommand::Service(s) => {
                if s.move_abs {
                    if s.axis == 0 || s.axis > 13 {
                        return Err(Rejection::new(
                            ErrorId::ENUM_OUT_OF_RANGE,
                            format!("pickplace: eServiceAxis = {} is not 1 … 13", s.axis),
                        ));
                    }
                    Self::finite("lrServicePos", s.pos)?;
                    for (f, v) in [
                        ("lrServiceVel", s.vel),
                        ("lrServiceAcc", s.acc),
                        ("lrServiceDec", s.dec),
                        ("lrServiceJerk", s.jerk),
                    ] {
                        crate::params::check_positive(f, v)?;
                    }
                }
                self.inputs.service = s;
            }
            PickPlaceCommand::SimSetBeltVelocity {
                belt,
                velocity,
                acceleration,
            } => {
                let n = Self::belt_checked(belt)?;
                Self::finite("velocity", velocity)?;
                Self::finite("acceleration", acceleration)?;
                if acceleration < 0.0 {
                    return Err(Rejection::new(
                        ErrorId::VALUE_OUT_OF_RANGE,
                        format!("belt {n}: acceleration = {acceleration} must be >= 0"),
                    ));
                }
                let a = &mut self.belts[n - 1].axis;
                a.target_velocity = velocity;
                a.acceleration = acceleration;
            }
            PickPlaceCommand::SimSetDigitalInputs {
                hw_limit_pos,
                hw_limit_neg,
                home_switch,
                enable_hw_limit,
            } => {
                self.inputs.hw_limit_pos = hw_limit_pos;
                self.inputs.hw_limit_neg = hw_limit_neg;
                self.inputs.home_abs_switch = home_switch;
                self.inputs.group_enable_hw_limit = enable_hw_limit;
            }
            PickPlaceCommand::SimInjectFault { axis, kind } => {
                if axis == 0 || axis > 13 {
                    return Err(Rejection::new(
                        ErrorId::ENUM_OUT_OF_RANGE,
                        format!(
                            "pickplace: fault axis = {axis} ({}) is not 1 … 13",
                            axis_name(axis)
                        ),
                    ));
                }
                self.pending_faults.push((axis, kind));
            }
        }
        Ok(id)
    }
}
