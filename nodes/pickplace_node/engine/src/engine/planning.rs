//! Profile planning (pick_and_place.md §7, §11, §15): static and belt targets, park paths,
//! the intercept prediction of §15.2, eligibility (§15.3), the resume after jogging (§9.2).

use super::*;

impl PickPlaceEngine {
    pub(super) fn bound_frame(&self) -> Option<MovingFrame> {
        match &self.motion {
            Motion::Bound { frame, .. } => Some(MovingFrame {
                c: Vec3::zeros(),
                s_ref: self.belt_s(frame.belt),
                ..*frame
            }),
            _ => None,
        }
    }

    /// The pose of a belt-bound TCP at this cycle's belt position (belts move before the TM).
    pub(super) fn refresh_bound_pose(&mut self) {
        if let Motion::Bound { frame, base, .. } = &self.motion {
            let p = v3(base) + frame.delta(self.belt_s(frame.belt));
            self.pose = *base;
            self.pose[0] = p.x;
            self.pose[1] = p.y;
            self.pose[2] = p.z;
        }
    }

    pub(super) fn shape(par: &ScPar) -> ShapeParams {
        ShapeParams {
            elliptical: par.path_mode() == PathMode::Elliptical,
            blending_radius: par.blending_radius,
            z_dist_elliptical: par.z_dist_elliptical,
        }
    }

    /// Ellipse preconditions other than ACS (§7.4): no A/B rotation of an involved frame.
    pub(super) fn ellipse_allowed(&self, belts: &[usize], static_wcs: bool) -> bool {
        let ab_free = |o: &[f64; 6]| o[3] == 0.0 && o[4] == 0.0;
        belts
            .iter()
            .all(|b| ab_free(&self.belts[b - 1].par.conveyor_belt_origin))
            && (!static_wcs || ab_free(&self.cfg.wcs_to_mcs))
    }

    /// The profile's `scPar` with the AXIS_REF limits of the group configuration folded into the
    /// `…Max…` values, so a static profile keeps them already at planning (§7.8 (1)); what the
    /// belt superposition adds is limited at the interpolation stage (`axis_ref`, §7.8 (2)).
    /// With the identity kinematics A1 … A6 move like X … C, so both limits apply to one axis.
    pub(super) fn with_axis_ref_limits(&self, par: &ScPar) -> ScPar {
        let mut p = par.clone();
        let fold = |a: f64, b: f64| match (a > 0.0, b > 0.0) {
            (true, true) => a.min(b),
            (true, false) => a,
            (false, _) => b,
        };
        for q in 0..7 {
            let joint = if q < 6 { q + 7 } else { 13 };
            for i in [pose_axis_index(q), joint] {
                let a = self.cfg.axis(i);
                p.max_vel[q] = fold(p.max_vel[q], a.max_vel);
                p.max_acc_dec[q] = fold(p.max_acc_dec[q], a.max_acc);
                p.max_jerk[q] = fold(p.max_jerk[q], a.max_jerk);
            }
        }
        p
    }

    pub(super) fn make_run(
        &mut self,
        geom: PathGeometry,
        start: [f64; 7],
        end: [f64; 7],
        fa: Option<MovingFrame>,
        fb: Option<MovingFrame>,
        par: &ScPar,
    ) -> Result<PathRun, ErrorId> {
        if geom.fallback_linear {
            self.set_warning(ids::ELLIPSE_FALLBACK_LINEAR);
        }
        let par = self.with_axis_ref_limits(par);
        let mut run =
            PathRun::new(geom, start, end, fa, fb, &par).map_err(|_| ids::INVALID_PARAMETER)?;
        run.set_override(self.applied_override);
        Ok(run)
    }

    /// Starts a job from the current pose: plans its first phase (§7, §15).
    pub(super) fn start_job(&mut self, job: Job) -> Result<Running, ErrorId> {
        let par = job.par.clone();
        // ACS is never a supported target frame (§7.1): checked before the profile parameters.
        if job.target == Target::Static && par.coord_system() == CoordSystem::Acs {
            return Err(ids::COORD_SYSTEM_NOT_SUPPORTED);
        }
        if par.path_mode() == PathMode::Elliptical
            && par.z_dist_elliptical <= 0.0
            && !matches!(job.target, Target::ParkOnly(_))
        {
            return Err(ids::INVALID_PARAMETER);
        }
        self.refresh_bound_pose();
        let frame_a = self.bound_frame();
        let start = self.pose;
        let gripper_enabled = par.gripper_closing_time != 0.0 || par.gripper_open_time != 0.0;
        let (lead, kind) = match job.role {
            Role::External | Role::Pick => (par.gripper_closing_time, GripperEvent::Close),
            Role::Place => (par.gripper_open_time, GripperEvent::Open),
        };
        let gripper = Gripper {
            enabled: gripper_enabled && !matches!(job.target, Target::ParkOnly(_)),
            active: gripper_enabled && (self.applied_override - 1.0).abs() < 1e-12,
            lead,
            kind,
            pulsed: false,
            after: None,
        };
        let belt_target = match (job.target, par.coord_system()) {
            (Target::Belt(n), _) => Some(n),
            (Target::Static, CoordSystem::Pcs(n)) => Some(n as usize),
            _ => None,
        };
        let phase = match (job.target, belt_target) {
            (Target::ParkOnly(n), _) => self.plan_park(&par, n, frame_a, false)?,
            (_, None) => {
                let cs = par.coord_system();
                let mut t = par.target_pos;
                match cs {
                    CoordSystem::Acs => return Err(ids::COORD_SYSTEM_NOT_SUPPORTED),
                    // Handled as a belt target below; kept for exhaustiveness.
                    CoordSystem::Pcs(_) => return Err(ids::COORD_SYSTEM_NOT_SUPPORTED),
                    CoordSystem::Wcs => {
                        let w = &self.cfg.wcs_to_mcs;
                        let f = crate::belt::BeltFrame::from_par(&crate::params::ConveyorBeltPar {
                            conveyor_belt_origin: *w,
                            ..Default::default()
                        });
                        let p = f.to_mcs(Vec3::new(t[0], t[1], t[2]));
                        t[0] = p.x;
                        t[1] = p.y;
                        t[2] = p.z;
                    }
                    CoordSystem::Mcs => {}
                }
                let (up_a, zs, belts) = match frame_a {
                    Some(f) => {
                        let b = &self.belts[f.belt - 1];
                        (b.frame().up(), b.par.z_dist_belt, vec![f.belt])
                    }
                    None => (Vec3::z(), par.z_start_dist, vec![]),
                };
                let s = v3(&start);
                let tt = v3(&t);
                let pts = ProfilePoints {
                    s,
                    ip1: s + up_a * zs,
                    ip2: tt + Vec3::z() * par.z_target_dist,
                    t: tt,
                };
                let mut shape = Self::shape(&par);
                if shape.elliptical && !self.ellipse_allowed(&belts, cs == CoordSystem::Wcs) {
                    shape.elliptical = false;
                    self.set_warning(ids::ELLIPSE_FALLBACK_LINEAR);
                }
                let geom = geometry::pick_place(&pts, &shape);
                let mut run = self.make_run(geom, start, t, frame_a, None, &par)?;
                run.points = Some(pts);
                Phase::Path {
                    run: Box::new(run),
                    leg: Leg::Main,
                    belt: None,
                    workpiece: None,
                }
            }
            (_, Some(n)) => {
                if !(1..=MAX_BELTS).contains(&n) || !self.belts[n - 1].par.is_configured() {
                    return Err(ids::BELT_NOT_CONFIGURED);
                }
                match self.plan_belt_leg(&job, n, frame_a, false)? {
                    Some((run, wp)) => Phase::Path {
                        run: Box::new(run),
                        leg: Leg::Main,
                        belt: Some(n),
                        workpiece: Some(wp),
                    },
                    None => self.plan_park(&par, n, frame_a, true)?,
                }
            }
        };
        // xInTarget / xInParkPos stay until the TCP actually leaves (first motion of this job).
        self.in_position_target = None;
        if let Phase::WaitPark { .. } = phase {
            self.in_target = false;
        }
        if let Phase::Path { run, .. } = &phase {
            self.precalc_time = run.precalc_time();
        }
        if !self.in_target {
            self.target_out = job.set_target;
        }
        let mut r = Running {
            job,
            phase,
            gripper,
            replan: false,
            active_emitted: false,
            hold_pose: start,
        };
        if let Phase::WaitPark { .. } = r.phase {
            self.at_park = true;
        }
        r.hold_pose = start;
        Ok(r)
    }

    /// Park path (§7.6) or, when already there, waiting at the park pose.
    pub(super) fn plan_park(
        &mut self,
        par: &ScPar,
        n: usize,
        frame_a: Option<MovingFrame>,
        wait: bool,
    ) -> Result<Phase, ErrorId> {
        let bp = self.belts[n - 1].par;
        let park = [
            bp.park_pos[0],
            bp.park_pos[1],
            bp.park_pos[2],
            bp.park_pos[3],
            bp.park_pos[4],
            bp.park_pos[5],
            self.pose[6],
        ];
        let s = v3(&self.pose);
        if frame_a.is_none() && (s - v3(&park)).norm() < PARK_TOLERANCE {
            if wait {
                return Ok(Phase::WaitPark {
                    belt: n,
                    prep_left: None,
                });
            }
            return Ok(Phase::Done);
        }
        let (up, zs) = match frame_a {
            Some(f) => {
                let b = &self.belts[f.belt - 1];
                (b.frame().up(), b.par.z_dist_belt)
            }
            None => (Vec3::z(), par.z_start_dist),
        };
        let ipp = s + up * (zs + par.z_dist_elliptical);
        let geom = geometry::park_path(
            s,
            ipp,
            v3(&park),
            par.z_dist_elliptical + par.blending_radius,
            ParkDirection::ToPark,
        );
        let start = self.pose;
        let run = self.make_run(geom, start, park, frame_a, None, par)?;
        Ok(Phase::Path {
            run: Box::new(run),
            leg: Leg::ToPark,
            belt: Some(n),
            workpiece: None,
        })
    }

    /// The next eligible workpiece on belt n and a path to it with the intercept prediction of
    /// §15.2; `None` if no workpiece is reachable yet (→ park). Missed workpieces are deleted.
    pub(super) fn plan_belt_leg(
        &mut self,
        job: &Job,
        n: usize,
        frame_a: Option<MovingFrame>,
        from_park: bool,
    ) -> Result<Option<(PathRun, u64)>, ErrorId> {
        let par = self.with_axis_ref_limits(&job.par);
        // eTargetCoordSystem = PCS n: the static target values are an offset in the PCS (§7.1).
        let offset = match (job.target, par.coord_system()) {
            (Target::Static, CoordSystem::Pcs(_)) => {
                Vec3::new(par.target_pos[0], par.target_pos[1], par.target_pos[2])
            }
            _ => Vec3::zeros(),
        };
        loop {
            let belt = &self.belts[n - 1];
            let preferred = job.preferred_wp.and_then(|id| {
                belt.workpieces
                    .iter()
                    .find(|w| w.id == id && w.state == WorkpieceState::Visible)
            });
            let Some(wp) = preferred
                .or_else(|| {
                    belt.workpieces
                        .iter()
                        .find(|w| w.state == WorkpieceState::Visible && !w.reserved)
                })
                .copied()
            else {
                return Ok(None);
            };
            let bp = belt.par;
            let x_now = belt.belt_x(&wp);
            if x_now > bp.upper_sync_limit {
                self.delete_workpiece(n, wp.id, WorkpieceEventKind::Missed);
                continue;
            }
            if x_now < bp.lower_sync_limit {
                return Ok(None);
            }
            let frame = belt.frame();
            let dir = frame.direction();
            let up = frame.up();
            let v = belt.axis.velocity;
            let s_now = belt.axis.position;
            let x_wp0 = belt.workpiece_mcs(&wp) + frame.rotation * offset;
            let aux1 = belt.aux1_target_pos;
            let start = self.pose;
            let c = norm_angle_near(bp.conveyor_belt_origin[5] + wp.initial[5], start[5]);
            let end = [0.0, 0.0, 0.0, par.target_pos[3], par.target_pos[4], c, aux1];
            let mut belts_involved = vec![n];
            if let Some(f) = frame_a {
                belts_involved.push(f.belt);
            }
            let (up_a, zs) = match frame_a {
                Some(f) => {
                    let b = &self.belts[f.belt - 1];
                    (b.frame().up(), b.par.z_dist_belt)
                }
                None => (Vec3::z(), par.z_start_dist),
            };
            let mut shape = Self::shape(&par);
            if shape.elliptical && !self.ellipse_allowed(&belts_involved, false) {
                shape.elliptical = false;
                self.set_warning(ids::ELLIPSE_FALLBACK_LINEAR);
            }
            let s = v3(&start);
            let mut tau = 0.0;
            let mut xhat = x_wp0;
            let mut plan: Option<PathRun> = None;
            let mut pts_rec = None;
            for _ in 0..PREDICTION_ITERATIONS {
                let new_xhat = x_wp0 + dir * (v * tau);
                let converged = plan.is_some() && (new_xhat - xhat).norm() < PREDICTION_TOLERANCE;
                xhat = new_xhat;
                let geom = if from_park {
                    let ipp = xhat + up * (bp.z_dist_belt + par.z_dist_elliptical);
                    geometry::park_path(
                        s,
                        ipp,
                        xhat,
                        par.z_dist_elliptical + par.blending_radius,
                        ParkDirection::FromPark,
                    )
                } else {
                    let pts = ProfilePoints {
                        s,
                        ip1: s + up_a * zs,
                        ip2: xhat + up * bp.z_dist_belt,
                        t: xhat,
                    };
                    pts_rec = Some(pts);
                    geometry::pick_place(&pts, &shape)
                };
                let mut e = end;
                e[0] = xhat.x;
                e[1] = xhat.y;
                e[2] = xhat.z;
                let fa = frame_a;
                let run = PathRun::new(geom, start, e, fa, None, &par)
                    .map_err(|_| ids::INVALID_PARAMETER)?;
                tau = run.time_to_sigma(run.geom.coupling_window.1);
                plan = Some(run);
                if converged {
                    break;
                }
            }
            let Some(mut run) = plan else {
                return Ok(None);
            };
            run.points = pts_rec;
            // Missed if the workpiece leaves the working area before the coupling end (§15.3).
            if x_now + v * tau > bp.upper_sync_limit {
                self.delete_workpiece(n, wp.id, WorkpieceEventKind::Missed);
                continue;
            }
            if run.geom.fallback_linear {
                self.set_warning(ids::ELLIPSE_FALLBACK_LINEAR);
            }
            run.frame_b = Some(MovingFrame {
                belt: n,
                dir,
                s_ref: s_now,
                c: x_wp0 - xhat,
            });
            run.set_override(self.applied_override);
            if let Some(w) = self.belts[n - 1]
                .workpieces
                .iter_mut()
                .find(|w| w.id == wp.id)
            {
                w.reserved = true;
            }
            return Ok(Some((run, wp.id)));
        }
    }

    /// Deletes the missed workpieces of belt n (§14) and reports them (no alloc).
    pub(super) fn delete_missed_on(&mut self, n: usize) {
        let mut ids = std::mem::take(&mut self.scratch_ids);
        ids.clear();
        self.belts[n - 1].delete_missed(&mut ids);
        for &id in &ids {
            let ev = CellEvent::Workpiece {
                cycle: self.cycle,
                belt: n as u8,
                id,
                kind: WorkpieceEventKind::Missed,
            };
            self.push_event(ev);
        }
        self.scratch_ids = ids;
    }

    pub(super) fn delete_workpiece(&mut self, n: usize, id: u64, kind: WorkpieceEventKind) {
        self.belts[n - 1].workpieces.retain(|w| w.id != id);
        let e = CellEvent::Workpiece {
            cycle: self.cycle,
            belt: n as u8,
            id,
            kind,
        };
        self.push_event(e);
    }

    pub(super) fn make_job(&mut self, set_target: u8, id: Option<CmdId>) -> Job {
        self.latched_set_target = set_target;
        let mode = self.par.tracking_mode;
        let (target, role, st) = match mode {
            1 => (Target::Static, Role::Pick, 0),
            2 | 3 => (Target::Belt(1), Role::Pick, 1),
            4 => (Target::Belt(2), Role::Pick, 2),
            _ => {
                // Only CV1 … CV5 are selectable (§1); anything else fails with 90005 at planning.
                let t = match set_target {
                    0 => Target::Static,
                    1..=5 => Target::Belt(set_target as usize),
                    _ => Target::Belt(0),
                };
                (t, Role::External, set_target)
            }
        };
        Job {
            id,
            par: self.par.clone(),
            target,
            role,
            set_target: st,
            mode,
            preferred_wp: None,
        }
    }

    /// The next leg of an endless mode after `prev` (§11).
    pub(super) fn next_leg(&self, prev: &Job) -> Job {
        let place = prev.role == Role::Pick;
        let (target, st) = match (prev.mode, place) {
            (1, true) => (Target::Belt(1), 1),
            (1, false) => (Target::Static, 0),
            (2, true) => (Target::Static, 0),
            (2, false) => (Target::Belt(1), 1),
            (3, true) => (Target::Belt(2), 2),
            (3, false) => (Target::Belt(1), 1),
            (4, true) => (Target::Belt(1), 1),
            _ => (Target::Belt(2), 2),
        };
        Job {
            id: None,
            par: self.par.clone(),
            target,
            role: if place { Role::Place } else { Role::Pick },
            set_target: st,
            mode: prev.mode,
            preferred_wp: None,
        }
    }

    /// The held path continued from the current (jogged) pose: a straight move to the next
    /// not-yet-passed profile point (IP1, IP2 or T), then the rest of the profile (§9.2 proposal).
    /// `None` when the path is coupled to a belt or has no profile points (park legs): re-plan.
    pub(super) fn path_after_jog(&mut self, run: &PathRun, par: &ScPar) -> Option<PathRun> {
        let pts = run.points?;
        if run.coupled() || (run.frame_a.is_some() && run.k() < 1.0) {
            return None;
        }
        let passed = run.points_passed().clamp(0, 2) as usize;
        let mut shape = Self::shape(par);
        let rest_pts = match passed {
            0 => ProfilePoints {
                s: pts.ip1,
                ip1: pts.ip1,
                ..pts
            },
            1 => {
                shape.elliptical = false;
                ProfilePoints {
                    s: pts.ip2,
                    ip1: pts.ip2,
                    ip2: pts.ip2,
                    t: pts.t,
                }
            }
            _ => {
                shape.elliptical = false;
                ProfilePoints {
                    s: pts.t,
                    ip1: pts.t,
                    ip2: pts.t,
                    t: pts.t,
                }
            }
        };
        if shape.elliptical && par.z_dist_elliptical <= 0.0 {
            shape.elliptical = false;
        }
        let rest = geometry::pick_place(&rest_pts, &shape);
        let geom = geometry::prepend_line(v3(&self.pose), &rest, passed);
        let mut nr = self
            .make_run(geom, self.pose, run.end_pose, None, run.frame_b, par)
            .ok()?;
        nr.points = Some(pts);
        Some(nr)
    }
}
