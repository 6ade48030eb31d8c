//! Linear master/slave coupling: MC_GearIn / MC_GearOut (single_axis.md §4.12.1, §4.12.3,
//! §2.5, W10). The slave follows the master's set position (or actual position with
//! AxisCoupleSlaveToActualValues, 1064) in the same cycle: masters are stepped before their
//! slaves. `SlavePos = SlavePos(t0) + ratio·(MasterPos − MasterPos(t0))`.

use motion_core::State1;

/// An active coupling of this axis as slave.
#[derive(Clone, Copy, Debug)]
pub struct Coupling {
    /// The master axis (index).
    pub master: usize,
    /// Effective gear ratio (RatioNumerator / RatioDenominator, or r_eff of MC_GearInDyn).
    pub ratio: f64,
    /// Master position at the coupling instant, in the master's raw coordinates (so that
    /// MC_SetPosition/homing on the master do not move the slave).
    pub m0: f64,
    /// Slave set position at the coupling instant.
    pub s0: f64,
    /// MC_GearInDyn: velocity-type coupling with a slewed ratio.
    pub dynamic: Option<DynCoupling>,
    /// Phasing offset and MC_GearInMultiMaster data (set/phasing.rs, multi_master.rs).
    pub ext: crate::added::CouplingExt,
}

/// State of an MC_GearInDyn coupling (§4.12.2): `ratio` of [`Coupling`] is r_eff.
#[derive(Clone, Copy, Debug)]
pub struct DynCoupling {
    /// The enabled MC_GearInDyn instance (None after Enable↓: ratio frozen).
    pub owner: Option<motion_core::CmdId>,
    /// GearRatio input.
    pub target: f64,
    /// Slew rate |dr/dt| = Acceleration / master AxisMaxVelocity \[1/s\].
    pub rate: f64,
    /// Master raw position of the previous cycle.
    pub m_prev: f64,
}

/// What a slave reads from its master each cycle.
#[derive(Clone, Copy, Debug)]
pub struct MasterState {
    /// Master set position, velocity and acceleration.
    pub set: State1,
    /// Master actual position \[u\].
    pub act_pos: f64,
    /// Master actual velocity \[u/s\].
    pub act_velo: f64,
    /// The master's coordinate offset (raw = position − offset).
    pub coord_offset: f64,
}
