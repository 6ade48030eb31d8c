//! §2.3 command admissibility matrix, cell by cell.
//!
//! `CASES` is the spec's table (✓/✗ per command and mode, with the "standing" qualifiers).
//! Every cell is checked against [`planar_engine::admissible`]; the cells of the modes
//! reachable without tracks (FM, CRF, ESG) are also driven through the engine, where a ✗
//! must give E_INVALID_COMMAND_MODE and a ✓ anything else.

mod common;
use common::*;
use planar_engine::*;

use CommandKind as K;
use CommandMode::*;

const MODES: [CommandMode; 7] = [
    FreeMovement,
    CRotationFreeMovement,
    JoiningTrack,
    OnTrack,
    CRotationOnTrack,
    LeavingTrack,
    ExternalSetpointGeneration,
];

/// Cell values: Y accepted, N rejected, S accepted only while standing.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cell {
    Y,
    N,
    S,
}
use Cell::*;

/// Rows of §2.3:                          FM CRF JT OT CRO LT ESG
const CASES: [(K, [Cell; 7]); 12] = [
    (
        K::MoveToPosition,
        /*              */ [Y, N, N, N, N, N, N],
    ),
    (
        K::JoinTrack,
        /*                   */ [Y, N, N, N, N, N, N],
    ),
    (
        K::LeaveTrack,
        /*                  */ [N, N, N, Y, N, N, N],
    ),
    (
        K::MoveOnTrack,
        /*                 */ [N, N, N, Y, N, N, N],
    ),
    (
        K::GearIn,
        /*                      */ [N, N, N, Y, N, N, N],
    ),
    (
        K::MoveC,
        /*                       */ [Y, Y, N, S, Y, N, N],
    ),
    (
        K::AdoptTrackOrientation,
        /*       */ [N, N, N, S, Y, N, N],
    ),
    (
        K::MoveZab,
        /*                     */ [Y, Y, N, Y, Y, N, N],
    ),
    (
        K::Halt,
        /*                        */ [Y, Y, N, Y, Y, N, Y],
    ),
    (
        K::StartEsgAbsolute,
        /*            */ [S, N, N, N, N, N, N],
    ),
    (
        K::StartEsgRelative,
        /*            */ [Y, Y, N, Y, Y, N, N],
    ),
    (
        K::GroupMembership,
        /*             */ [S, S, N, S, S, N, N],
    ),
];

#[test]
fn matrix_every_cell_pure() {
    let mut n = 0;
    for (kind, row) in CASES {
        for (mode, cell) in MODES.iter().zip(row) {
            for standing in [true, false] {
                // ESG is "active" in the ESG column only (absolute ESG is the mode).
                let ctx = AdmissionContext {
                    standing,
                    esg_active: *mode == ExternalSetpointGeneration,
                };
                let expect = match cell {
                    Y => true,
                    N => false,
                    S => standing,
                };
                assert_eq!(
                    admissible(kind, *mode, ctx),
                    expect,
                    "row {kind:?}, column {mode:?}, standing {standing}"
                );
                n += 1;
            }
        }
    }
    assert_eq!(n, 12 * 7 * 2);
}

/// StopExternalSetpointGeneration: only while ESG (absolute or relative) is active.
#[test]
fn matrix_stop_esg_row() {
    for mode in MODES {
        for esg_active in [false, true] {
            let ctx = AdmissionContext {
                standing: true,
                esg_active,
            };
            assert_eq!(
                admissible(K::StopEsg, mode, ctx),
                esg_active,
                "{mode:?} esg {esg_active}"
            );
        }
    }
}

/// Brings a fresh mover M into `mode` (FM, CRF or ESG); a second mover N stays away.
fn in_mode(mode: CommandMode) -> Sim {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0), ("N", 2000.0, 0.0)]);
    s.enable("M");
    s.enable_group("G");
    match mode {
        FreeMovement => {}
        CRotationFreeMovement => {
            let id = s.ok(move_c("M", 45.0));
            s.wait_final(id, 5.0);
            s.step();
        }
        ExternalSetpointGeneration => {
            s.ok(PlanarCommand::StartExternalSetpointGeneration {
                mover: "M".into(),
                options: Default::default(),
            });
        }
        _ => unreachable!(),
    }
    s.step();
    assert_eq!(s.mover("M").command_mode, mode);
    s
}

fn command_for(kind: K) -> Option<PlanarCommand> {
    let mover = "M".to_string();
    let constraint = DynamicConstraint::default();
    Some(match kind {
        K::MoveToPosition => PlanarCommand::MoveToPosition {
            mover,
            target_position: PositionXYC::new(300.0, 0.0, 0.0),
            constraint,
            options: MoveToPositionOptions {
                use_orientation: false,
            },
        },
        K::MoveC => PlanarCommand::MoveC {
            mover,
            target_position: 90.0,
            constraint,
            options: Default::default(),
        },
        K::MoveZab => PlanarCommand::MoveZ {
            mover,
            target_position: 3.0,
            constraint,
        },
        K::Halt => PlanarCommand::Halt { mover, constraint },
        K::StartEsgAbsolute => PlanarCommand::StartExternalSetpointGeneration {
            mover,
            options: Default::default(),
        },
        K::StartEsgRelative => PlanarCommand::StartExternalSetpointGeneration {
            mover,
            options: ExternalSetpointGenerationOptions {
                mode: ExternalSetpointMode::Relative,
            },
        },
        K::GroupMembership => PlanarCommand::MoverAddToGroup {
            mover,
            group: "G".into(),
        },
        // Track commands arrive with the track engine (part 2).
        K::JoinTrack
        | K::LeaveTrack
        | K::MoveOnTrack
        | K::GearIn
        | K::AdoptTrackOrientation
        | K::StopEsg => return None,
    })
}

#[test]
fn matrix_reachable_columns_through_engine() {
    let mut checked = 0;
    for (kind, row) in CASES {
        for (col, mode) in MODES.iter().enumerate() {
            if !matches!(
                mode,
                FreeMovement | CRotationFreeMovement | ExternalSetpointGeneration
            ) {
                continue;
            }
            let Some(cmd) = command_for(kind) else {
                continue;
            };
            let mut s = in_mode(*mode);
            let before = s.mover("M");
            let r = s.cmd(cmd);
            match row[col] {
                N => {
                    let e = r.expect_err("✗ cell accepted");
                    assert_eq!(
                        e.error_id,
                        errors::E_INVALID_COMMAND_MODE,
                        "row {kind:?}, column {mode:?}: {e}"
                    );
                    s.step();
                    let after = s.mover("M");
                    assert_eq!(
                        (before.command_mode, before.set_pos),
                        (after.command_mode, after.set_pos),
                        "a rejection changes nothing"
                    );
                }
                Y | S => {
                    if let Err(e) = r {
                        assert_ne!(
                            e.error_id,
                            errors::E_INVALID_COMMAND_MODE,
                            "row {kind:?}, column {mode:?}: {e}"
                        );
                    }
                }
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 7 * 3);
}

/// The "standing" qualifier of StartEsgAbsolute and AddToGroup in FM, through the engine.
#[test]
fn matrix_standing_cells_through_engine() {
    for kind in [K::StartEsgAbsolute, K::GroupMembership] {
        let mut s = in_mode(FreeMovement);
        let mv = s.ok(mtp("M", 500.0, 0.0, 0.0));
        s.steps(5);
        let e = s
            .cmd(command_for(kind).unwrap())
            .expect_err("accepted while moving");
        assert!(
            matches!(
                e.error_id,
                errors::E_INVALID_COMMAND_MODE | errors::E_INVALID_STATE
            ),
            "{kind:?}: {e}"
        );
        s.wait_final(mv, 5.0);
        s.cmd(command_for(kind).unwrap())
            .expect("accepted when standing");
    }
    // StopEsg without ESG.
    let mut s = in_mode(FreeMovement);
    let e = s.err(PlanarCommand::StopExternalSetpointGeneration { mover: "M".into() });
    assert_eq!(e.error_id, errors::E_INVALID_COMMAND_MODE);
}
