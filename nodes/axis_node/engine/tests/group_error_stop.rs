//! A member error stops the whole group (plcopen_platform.md §5: any member error puts the
//! group in GROUP_ERROR_STOP; issue 17 item 1): every member brakes with the group's error
//! reaction on the path (the error's reaction class, §7.2: 1 = the programmed deceleration,
//! 2 = quick stop with the members' fast limits; an error that is no MC message counts as
//! class 2) and ends at standstill, the group in GROUP_ERROR_STOP. Before, the healthy member
//! ran on alone and left the path.
mod p4rig;
use axis_engine::group::*;
use axis_engine::platform::*;
use axis_engine::MotionState;
use p4rig::*;

fn mc_message(axis: &str, reaction: u16) -> PlatformCommand {
    PlatformCommand::InjectMcMessage {
        axis: axis.into(),
        error_id: 24001,
        behebungs_klasse: 1,
        reaktions_klasse: reaction,
    }
}

/// The run: (300000, 400000) at 1e5 u/s, y's MC error after 0.3 s. Returns the
/// members' stop distances along the path and the cycles the stop took.
fn error_during_a_group_move(reaction: u16) -> (f64, usize) {
    let mut r = P4::isg_xy(PlatformConfig::default());
    let m = r.gid(lin_rel(vec![300_000.0, 400_000.0], 1e5));
    r.steps(300);
    let (x0, y0) = (r.ax("x").set_pos, r.ax("y").set_pos);
    r.p(mc_message("y", reaction)).unwrap();
    let cycles = r.until(20_000, |r| {
        r.ax("x").set_velo == 0.0 && r.ax("y").set_velo == 0.0
    });
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
    assert!(r.out(m).error, "the group move ends with Error");
    let (x, y) = (r.ax("x"), r.ax("y"));
    assert_eq!(
        x.motion_state,
        MotionState::Standstill,
        "healthy member at rest"
    );
    assert_eq!(y.motion_state, MotionState::ErrorStop);
    // On the path: displacement 3:4 throughout (checked at the end; the interpolation is
    // one line).
    assert!(
        ((x.set_pos - x0) * 4.0 - (y.set_pos - y0) * 3.0).abs() < 1e-6,
        "left the path: x {x0} -> {}, y {y0} -> {}",
        x.set_pos,
        y.set_pos
    );
    let travelled = ((x.set_pos - x0).powi(2) + (y.set_pos - y0).powi(2)).sqrt();
    (travelled, cycles)
}

#[test]
fn a_member_error_brakes_every_member_on_the_path() {
    let (d1, c1) = error_during_a_group_move(1);
    let (d2, c2) = error_during_a_group_move(2);
    // Class 1 at the programmed path deceleration (1.25e6 u/s², the members' 1e6 over
    // the direction cosines; jerk 1.25e8): from 1e5 u/s about 0.1 s, 4000..12000 u.
    assert!(
        (4000.0..12_000.0).contains(&d1),
        "class 1 stop {d1} u in {c1} cycles"
    );
    // Class 2 quick stop with the fast limits (5e6 u/s², 1e9 u/s³ per member): shorter.
    assert!(d2 < d1 / 2.0, "class 2 stop {d2} u vs class 1 {d1} u");
    assert!(c2 < c1, "class 2 took {c2} cycles, class 1 {c1}");
}
