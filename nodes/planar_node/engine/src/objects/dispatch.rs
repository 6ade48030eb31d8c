//! Command dispatch: a `PlanarCommand` to the method that runs it (tracks: `crate::track`).

use super::*;

impl Objects {
    pub(crate) fn dispatch(
        &mut self,
        tracks: &mut dyn TrackHooks,
        cmd: PlanarCommand,
    ) -> Result<PlanarReply, Rejection> {
        use PlanarCommand as C;
        match cmd {
            C::EnvironmentClear => {
                if self.env.group.is_some() {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("environment '{}' is a group member", self.env.name),
                    ));
                }
                self.env.stators.clear();
                self.env.boundary = None;
                self.done_now()
            }
            C::AddStator { lower_x, lower_y } => self.env_add_stator(lower_x, lower_y),
            C::CreateBoundary => {
                let tiles = self.env_tiles_for_boundary();
                if tiles.is_empty() {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("environment '{}': no stators", self.env.name),
                    ));
                }
                self.env.boundary = Some(boundary_elements(&tiles));
                self.done_now()
            }
            C::EnvironmentAddToGroup { group } => {
                let g = self.group(&group)?;
                if self.groups[g].sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!(
                            "environment: group '{group}' is {:?}",
                            self.groups[g].sm.state
                        ),
                    ));
                }
                if self.env.boundary.is_none() && self.parts.is_empty() {
                    return Err(reject(E_INVALID_STATE, "environment: CreateBoundary first"));
                }
                if let Some(og) = self.env.group {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!(
                            "environment: already member of group '{}'",
                            self.groups[og].name
                        ),
                    ));
                }
                self.env.group = Some(g);
                self.groups[g].environment = true;
                self.done_now()
            }
            C::EnvironmentRemoveFromGroup => {
                if let Some(g) = self.env.group.take() {
                    self.groups[g].environment = false;
                }
                self.done_now()
            }
            C::EnvironmentGetPlanarObjectInfo => {
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::ObjectInfo(PlanarObjectInfo {
                        object_type: PlanarObjectType::Environment,
                        id: self.env.oid,
                    }),
                })
            }
            C::MoveToPosition {
                mover,
                target_position,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                self.move_to_position(tracks, i, target_position, constraint, options)
            }
            C::MoveZ {
                mover,
                target_position,
                constraint,
            } => {
                let i = self.mover(&mover)?;
                self.move_aux(i, 0, target_position, constraint)
            }
            C::MoveA {
                mover,
                target_position,
                constraint,
            } => {
                let i = self.mover(&mover)?;
                self.move_aux(i, 1, target_position, constraint)
            }
            C::MoveB {
                mover,
                target_position,
                constraint,
            } => {
                let i = self.mover(&mover)?;
                self.move_aux(i, 2, target_position, constraint)
            }
            C::MoveC {
                mover,
                target_position,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                self.move_c(tracks, i, target_position, constraint, options)
            }
            C::Halt { mover, constraint } => {
                let i = self.mover(&mover)?;
                self.halt(i, constraint)
            }
            C::MoverEnable { mover } => {
                let i = self.mover(&mover)?;
                self.enable_mover(i)
            }
            C::MoverDisable { mover } => {
                let i = self.mover(&mover)?;
                self.disable_mover(i)
            }
            C::MoverReset { mover } => {
                let i = self.mover(&mover)?;
                self.reset_mover(i)
            }
            C::SetPosition { mover, position } => {
                let i = self.mover(&mover)?;
                self.set_position(i, position)
            }
            C::StartExternalSetpointGeneration { mover, options } => {
                let i = self.mover(&mover)?;
                self.start_esg(i, options)
            }
            C::StopExternalSetpointGeneration { mover } => {
                let i = self.mover(&mover)?;
                self.stop_esg(i)
            }
            C::SetExternalSetpoint {
                mover,
                set_position,
                set_velocity,
                set_acceleration,
            } => {
                let i = self.mover(&mover)?;
                self.set_external_setpoint(
                    i,
                    Setpoint {
                        pos: set_position,
                        vel: set_velocity,
                        acc: set_acceleration,
                    },
                    None,
                )
            }
            C::SetExternalSetpointReferenceId {
                mover,
                set_position,
                set_velocity,
                set_acceleration,
                reference_system_oid,
            } => {
                let i = self.mover(&mover)?;
                self.set_external_setpoint(
                    i,
                    Setpoint {
                        pos: set_position,
                        vel: set_velocity,
                        acc: set_acceleration,
                    },
                    Some(reference_system_oid),
                )
            }
            C::MoverAddToGroup { mover, group } => {
                let i = self.mover(&mover)?;
                self.mover_add_to_group(i, &group)
            }
            C::MoverRemoveFromGroup { mover } => {
                let i = self.mover(&mover)?;
                self.mover_remove_from_group(i)
            }
            C::GetPositionOnCurrentPart { mover } => {
                let i = self.mover(&mover)?;
                self.position_on_current_part(i)
            }
            C::MoverGetPlanarObjectInfo { mover } => {
                let i = self.mover(&mover)?;
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::ObjectInfo(PlanarObjectInfo {
                        object_type: PlanarObjectType::Mover,
                        id: self.movers[i].oid,
                    }),
                })
            }
            C::GroupEnable { group } => {
                let g = self.group(&group)?;
                let id = self.new_id();
                let t = self.timing;
                let r = self.groups[g].sm.enable(
                    id,
                    &t,
                    &format!("group '{group}'"),
                    &mut self.pending,
                )?;
                ev(
                    &mut self.pending,
                    id,
                    if r == Accepted::AlreadyThere {
                        CommandState::Done
                    } else {
                        CommandState::Active
                    },
                );
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::None,
                })
            }
            C::GroupDisable { group } => {
                let g = self.group(&group)?;
                if let Some(&j) = self.groups[g]
                    .movers
                    .iter()
                    .find(|&&j| !self.movers[j].xy_standing() || self.movers[j].c.moving())
                {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!(
                            "group '{group}': member '{}' is moving",
                            self.movers[j].name
                        ),
                    ));
                }
                let id = self.new_id();
                let t = self.timing;
                let r = self.groups[g].sm.disable(id, &t, &mut self.pending);
                ev(
                    &mut self.pending,
                    id,
                    if r == Accepted::AlreadyThere {
                        CommandState::Done
                    } else {
                        CommandState::Active
                    },
                );
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::None,
                })
            }
            C::GroupReset { group } => {
                let g = self.group(&group)?;
                let id = self.new_id();
                let t = self.timing;
                let r = self.groups[g]
                    .sm
                    .reset(id, &t, &format!("group '{group}'"))?;
                ev(
                    &mut self.pending,
                    id,
                    if r == Accepted::AlreadyThere {
                        CommandState::Done
                    } else {
                        CommandState::Active
                    },
                );
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::None,
                })
            }
            C::PartInitialize { part, part_oid } => {
                let p = self.part(&part)?;
                if self.parts[p].oid != part_oid {
                    return Err(reject(
                        E_INVALID_PART,
                        format!(
                            "part '{part}': part_oid = 0x{part_oid:08X} is not its OID 0x{:08X}",
                            self.parts[p].oid
                        ),
                    ));
                }
                self.parts[p].initialized = true;
                self.done_now()
            }
            C::ActivatePosition {
                part,
                position_index,
            } => {
                let p = self.part(&part)?;
                self.activate_position(p, position_index)
            }
            C::AllowEnable { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                self.parts[p].force_disabled = false;
                self.reconcile_parts();
                self.done_now()
            }
            C::ForceDisable { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                self.parts[p].force_disabled = true;
                for i in 0..self.movers.len() {
                    if self.parts[p].contains(self.movers[i].cs, self.movers[i].xy_out().pos)
                        && Self::holds_parts(&self.movers[i])
                    {
                        self.mover_error(i, E_PART_DISABLED, ErrorReaction::Abort);
                    }
                }
                self.reconcile_parts();
                self.done_now()
            }
            C::PartReset { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                let id = self.new_id();
                let t = self.timing;
                let r = self.parts[p].sm.reset(id, &t, &format!("part '{part}'"))?;
                ev(
                    &mut self.pending,
                    id,
                    if r == Accepted::AlreadyThere {
                        CommandState::Done
                    } else {
                        CommandState::Active
                    },
                );
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::None,
                })
            }
            C::PartGetPosition { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                let (cs, o) = self.parts[p].origin();
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::Position(PositionXYC::with_ref(o.x, o.y, 0.0, cs)),
                })
            }
            C::InjectError {
                kind,
                name,
                reaction,
            } => {
                if reaction == ErrorReaction::None {
                    return Err(reject(
                        ErrorId::ENUM_OUT_OF_RANGE,
                        format!("InjectError '{name}': reaction None"),
                    ));
                }
                let t = self.timing;
                match kind {
                    ObjectKind::Mover => {
                        let i = self.mover(&name)?;
                        self.mover_error(i, E_OBJECT_ERROR, reaction);
                    }
                    ObjectKind::Group => {
                        let g = self.group(&name)?;
                        self.groups[g]
                            .sm
                            .error(E_OBJECT_ERROR, reaction, &t, &mut self.pending);
                    }
                    ObjectKind::Part => {
                        let p = self.part(&name)?;
                        // §2.6: the movers on the part fail first (QuickStop), then the part.
                        for i in 0..self.movers.len() {
                            if self.parts[p]
                                .contains(self.movers[i].cs, self.movers[i].xy_out().pos)
                            {
                                self.mover_error(i, E_PART_DISABLED, ErrorReaction::QuickStop);
                            }
                        }
                        self.parts[p]
                            .sm
                            .error(E_OBJECT_ERROR, reaction, &t, &mut self.pending);
                    }
                    ObjectKind::Track => {
                        tracks.inject_error(&name, reaction, &t, &mut self.pending)?;
                    }
                }
                self.done_now()
            }
            // Tracks and the on-track mover methods (§3.2, §3.3): crate::track.
            cmd => tracks.command(self, cmd),
        }
    }
}
