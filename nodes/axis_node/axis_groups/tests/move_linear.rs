//! Part 4 groups on a plain axis set, without the composed engine (issue 16: the group crate
//! has its own tests): members in Standby once powered, MC_MoveLinearAbsolute moves them on a
//! straight line in axis space and ends exactly on the target (plcopen_platform.md §3.2),
//! and the profile's velocity cap (a `GroupProfile`) limits the members.

use axis_groups::*;
use motion_core::{CommandState, ErrorId, Rejection};
use single_axis::axis::Axis;
use single_axis::handshake::Handshake;
use single_axis::set::{BufferMode, Power};
use single_axis::{AxisConfig, AxisSet};

const DT: f64 = 0.001;

/// Tc2_MC2 without safety functions; `cap` = every member's velocity cap.
struct Plain {
    cap: f64,
}

impl GroupProfile for Plain {
    fn isg(&self) -> bool {
        false
    }
    fn feed_hold(&self) -> bool {
        false
    }
    fn velocity_cap(&self, _ax: usize) -> f64 {
        self.cap
    }
    fn check_group_motion(
        &mut self,
        _axes: &mut [Axis],
        _fbs: &mut Handshake,
        _group: &str,
        _fb: &str,
        _members: &[usize],
        _absolute: bool,
        _dir: &[f64],
        _velocity: f64,
    ) -> Result<(), Rejection> {
        Ok(())
    }
}

struct Rig {
    set: AxisSet,
    groups: Groups,
    profile: Plain,
}

impl Rig {
    fn xy(cap: f64) -> Rig {
        let names = ["x", "y"];
        let mut set = AxisSet::new(
            names
                .iter()
                .map(|n| (n.to_string(), AxisConfig::default()))
                .collect(),
        )
        .unwrap();
        let mut groups = Groups::default();
        let cfg = [GroupConfig {
            name: "g".into(),
            axes: names.iter().map(|n| n.to_string()).collect(),
        }];
        groups.build(&cfg, &set.index, set.axes.len()).unwrap();
        for (ax, n) in names.iter().enumerate() {
            let p = Power {
                axis: n.to_string(),
                enable: true,
                enable_positive: true,
                enable_negative: true,
                override_percent: 100.0,
                buffer_mode: BufferMode::Aborting,
            };
            set.power(ax, p).unwrap();
        }
        let mut r = Rig {
            set,
            groups,
            profile: Plain { cap },
        };
        r.cycle();
        r
    }

    fn cx(&mut self) -> GroupCx<'_> {
        GroupCx {
            groups: &mut self.groups,
            axes: &mut self.set.axes,
            index: &self.set.index,
            fbs: &mut self.set.fbs,
            profile: &mut self.profile,
        }
    }

    fn cycle(&mut self) -> Vec<motion_core::CommandEvent> {
        self.set.begin_cycle();
        self.cx().groups_step(DT);
        self.set.step_axes(DT);
        self.set.end_cycle();
        std::mem::take(&mut self.set.fbs.events)
    }
}

fn line(position: Vec<f64>, velocity: f64) -> GroupCommand {
    GroupCommand::MoveLinearAbsolute(MoveLinear {
        group: "g".into(),
        position,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        coord_system: CoordSystem::Acs,
        buffer_mode: BufferMode::Aborting,
        transition_mode: TransitionMode::None,
    })
}

#[test]
fn move_linear_absolute_is_straight_and_ends_on_the_target() {
    let mut r = Rig::xy(f64::INFINITY);
    assert_eq!(r.groups.status(0, &r.set.axes).state, GroupState::Standby);
    let id = r
        .cx()
        .group_command(line(vec![300.0, -400.0], 250.0))
        .unwrap()
        .id;
    let mut done = false;
    for _ in 0..20000 {
        let (x, y) = (r.set.axes[0].set.pos, r.set.axes[1].set.pos);
        assert!((x * -4.0 - y * 3.0).abs() < 1e-6, "off the line: {x} {y}");
        if r.cycle()
            .iter()
            .any(|e| e.id == id && e.state == CommandState::Done)
        {
            done = true;
            break;
        }
    }
    assert!(done, "MC_MoveLinearAbsolute not Done");
    assert_eq!(
        (r.set.axes[0].set.pos, r.set.axes[1].set.pos),
        (300.0, -400.0)
    );
    assert_eq!(r.groups.status(0, &r.set.axes).state, GroupState::Standby);
}

#[test]
fn the_profiles_velocity_cap_limits_every_member() {
    let mut r = Rig::xy(50.0);
    r.cx()
        .group_command(line(vec![300.0, 400.0], 250.0))
        .unwrap();
    let mut peak: f64 = 0.0;
    for _ in 0..3000 {
        r.cycle();
        for a in &r.set.axes {
            peak = peak.max(a.set.vel.abs());
        }
    }
    assert!(
        peak > 49.0 && peak <= 50.0 + 1e-9,
        "peak member velocity {peak}"
    );
}

#[test]
fn unknown_groups_and_bad_positions_are_refused() {
    let mut r = Rig::xy(f64::INFINITY);
    let mut c = line(vec![1.0, 2.0], 10.0);
    if let GroupCommand::MoveLinearAbsolute(m) = &mut c {
        m.group = "nope".into();
    }
    assert_eq!(
        r.cx().group_command(c).unwrap_err().error_id,
        ErrorId::UNKNOWN_OBJECT
    );
    let e = r
        .cx()
        .group_command(line(vec![f64::NAN, 2.0], 10.0))
        .unwrap_err();
    assert_eq!(e.error_id, ErrorId::NOT_FINITE);
}
