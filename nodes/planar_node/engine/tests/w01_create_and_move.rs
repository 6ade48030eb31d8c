//! W1 – Create and move a mover (manual 6.1.3, xplanar.md §7).
//! Mover at (0,0,0); Enable; MoveToPosition((100,100,0)); final SetPos (100,100), c 0,
//! FreeMovement, busyXYC false.

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

#[test]
fn w01_create_and_move() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    assert_eq!(
        s.mover("M").state,
        PlanarState::Disabled,
        "start-up state Disabled (§1.11)"
    );
    assert_eq!(s.mover("M").command_mode, CommandMode::Invalid);
    s.enable("M");
    assert_eq!(s.mover("M").state, PlanarState::Enabled);
    assert_eq!(s.mover("M").command_mode, CommandMode::FreeMovement);
    let id = s.ok(mtp("M", 100.0, 100.0, 0.0));
    s.step();
    assert!(s.mover("M").busy.busy_xyc, "busyXYC during the move");
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    let m = s.mover("M");
    assert_pos(&m, 100.0, 100.0);
    assert!(close(m.set_pos.c, 0.0, ANG_TOL));
    assert_eq!(m.command_mode, CommandMode::FreeMovement);
    assert!(!m.busy.busy_xyc && !m.busy.busy_mover);
    assert_eq!(m.set_velo, MoverVector::default());
}

/// §5.1: rest-to-rest time T = S/v + v/a + a/j along the path (default dynamics:
/// v 1000, a 10000, j 100000 → 500 mm diagonal: 0.5 + 0.1 + 0.1 = 0.7 s).
#[test]
fn w01_duration_follows_the_path_profile() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let d = 500.0 / 2f64.sqrt();
    let id = s.ok(mtp("M", d, d, 0.0));
    let mut n = 0;
    let mut vmax: f64 = 0.0;
    while s.state(id) != Some(CommandState::Done) {
        s.step();
        n += 1;
        let v = s.mover("M").set_velo;
        vmax = vmax.max(v.x.hypot(v.y));
        assert!(n < 5000);
    }
    let t = n as f64 * 0.001;
    assert!((t - 0.7).abs() <= 0.002, "duration {t} s, expected 0.7 s");
    assert!(
        vmax <= 1000.0 + 1e-6 && vmax > 999.0,
        "tangential velocity limit, peak {vmax}"
    );
}
