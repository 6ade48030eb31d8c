//! The ISG profile's hooks on a plain axis set and group set, without the composed engine
//! (issue 16: the profile crate has its own tests): the FB catalogue (§3.1, 4905), order
//! slots (§6.2, R-HS-3/R-HS-4), start-up (§9, 4013), FB-level ids (§7.3), BufferMode forced
//! to MC_Aborting (§14) and the velocity clamp of non-referenced axes (R-SAF-6).

use axis_groups::Groups;
use isg_platform::ids::*;
use isg_platform::{
    AxisCall, AxisPlatformConfig, Platform, PlatformConfig, PlatformCx, PlatformProfile, PostKind,
    SIM,
};
use motion_core::{CmdId, Rejection};
use single_axis::error_ids::COMMAND_NOT_PERMITTED;
use single_axis::inputs::BufferMode;
use single_axis::{AxisConfig, AxisSet};

fn call<'a>(
    fb: &'static str,
    v: Option<&'a mut f64>,
    m: Option<&'a mut BufferMode>,
) -> AxisCall<'a> {
    AxisCall {
        fb,
        extension: false,
        motion: fb.starts_with("MC_Move") || fb == "MC_Halt" || fb == "MC_Stop",
        velocity: v,
        buffer_mode: m,
    }
}

struct Rig {
    platform: Platform,
    set: AxisSet,
    groups: Groups,
}

impl Rig {
    fn new(cfg: PlatformConfig) -> Rig {
        let mut r = Rig {
            platform: Platform::default(),
            set: AxisSet::new(vec![("x".into(), AxisConfig::default())]).unwrap(),
            groups: Groups::default(),
        };
        r.cx().build(PlatformProfile::IsgMcp, &cfg).unwrap();
        r
    }

    fn cx(&mut self) -> PlatformCx<'_> {
        PlatformCx {
            platform: &mut self.platform,
            set: &mut self.set,
            groups: &mut self.groups,
        }
    }

    /// One cycle of the profile around (idle) axes.
    fn cycle(&mut self) {
        self.set.begin_cycle();
        self.cx().step_pre();
        self.set.step_axes(0.001);
        self.cx().step_post();
        self.set.end_cycle();
    }

    fn screen(&mut self, c: &mut AxisCall<'_>) -> Result<(), Rejection> {
        self.cx().screen(0, c)
    }
}

#[test]
fn calls_are_classified_by_the_manuals_fb_names() {
    assert!(call("MC_MoveAbsolute", None, None).places_order());
    assert!(!call("MC_Power", None, None).places_order());
    assert!(!call("MC_ReadStatus", None, None).places_order());
    assert!(!call(SIM, None, None).places_order());
    assert_eq!(
        call("MC_Jog", None, None).not_in_catalogue(),
        Some("MC_Jog")
    );
    assert_eq!(call("MC_MoveAbsolute", None, None).not_in_catalogue(), None);
    let mut ext = call("MC_PhasingAbsolute", None, None);
    ext.extension = true;
    assert!(ext.not_in_catalogue().is_some());
    assert_eq!(
        call("MC_Stop", None, None).classify(),
        (true, PostKind::Stop)
    );
    assert_eq!(
        call("MC_SetOverride", None, None).classify(),
        (false, PostKind::Override)
    );
}

#[test]
fn start_up_catalogue_and_order_slots() {
    let mut r = Rig::new(PlatformConfig::default());
    // §9: orders during the start-up cycles → 4013; reads pass.
    let e = r
        .screen(&mut call("MC_MoveAbsolute", None, None))
        .unwrap_err();
    assert_eq!(e.error_id, ERR_PO_AX_TNA_INIT_STATE);
    assert!(r.screen(&mut call("MC_ReadStatus", None, None)).is_ok());
    for _ in 0..PlatformConfig::default().nr_cycles_chk_mc_runs {
        r.cycle();
    }
    // §3.1: not in the ISG catalogue → 4905.
    let e = r.screen(&mut call("MC_Jog", None, None)).unwrap_err();
    assert_eq!(e.error_id, ERR_SIM_NOT_IMPLEMENTED);
    // §14: no BufferMode, every order aborts.
    let mut mode = BufferMode::Buffered;
    r.screen(&mut call("MC_MoveAbsolute", None, Some(&mut mode)))
        .unwrap();
    assert_eq!(mode, BufferMode::Aborting);
    // R-HS-3: one order per axis and cycle (error 4); R-HS-4: MC_Stop overwrites.
    r.cx().accepted(0, true, PostKind::Other, CmdId(7));
    assert_eq!(r.platform.order_id(CmdId(7)), Some(1));
    let e = r
        .screen(&mut call("MC_MoveRelative", None, None))
        .unwrap_err();
    assert_eq!(e.error_id, FB_ERR_MC_DID_NOT_TAKE_ORDER);
    assert!(r.screen(&mut call("MC_Stop", None, None)).is_ok());
    // The next cycle frees the slot.
    r.cycle();
    assert!(r.screen(&mut call("MC_MoveRelative", None, None)).is_ok());
    // §7.3: Tc2_MC2 state refusals show as 4901.
    let e = r.cx().refused(Rejection::new(COMMAND_NOT_PERMITTED, "x"));
    assert_eq!(e.error_id, ERR_SIM_TRANSITION_NOT_ALLOWED);
}

#[test]
fn non_referenced_axes_move_slowly_and_only_relative() {
    let mut cfg = PlatformConfig::default();
    let axis = AxisPlatformConfig {
        referenced: false,
        vb_not_referenced: 50.0,
        ..AxisPlatformConfig::default()
    };
    cfg.axes.insert("x".into(), axis);
    let mut r = Rig::new(cfg);
    for _ in 0..10 {
        r.cycle();
    }
    let e = r
        .screen(&mut call("MC_MoveAbsolute", None, None))
        .unwrap_err();
    assert_eq!(e.error_id, ERR_SIM_AXIS_NOT_REFERENCED);
    let mut v = 500.0;
    r.screen(&mut call("MC_MoveRelative", Some(&mut v), None))
        .unwrap();
    assert_eq!(v, 50.0);
}
