//! The manual's enumerations of FB inputs (`MC_BufferMode`, `MC_Direction`, `E_JogMode`, ...,
//! single_axis.md §5.3): the vocabulary every layer of the axis engine shares. It owns the
//! numeric values and their checked conversion; it knows no FB, axis or engine.

/// Declares a manual enumeration with its numeric values and checked conversion (also used by
/// the engine crate for the enumerations of its own FBs).
#[macro_export]
macro_rules! raw_enum {
    ($(#[$m:meta])* $name:ident : $field:literal { $($(#[$vm:meta])* $var:ident = $val:expr),+ $(,)? }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum $name {
            $($(#[$vm])* $var = $val),+
        }
        impl $name {
            /// Converts the manual's numeric value; unknown values are refused with
            /// `ENUM_OUT_OF_RANGE` and a message naming the field and value.
            pub fn from_raw(value: u32) -> Result<Self, motion_core::Rejection> {
                match value {
                    $(v if v == $val => Ok($name::$var),)+
                    _ => Err(motion_core::Rejection::new(
                        motion_core::ErrorId::ENUM_OUT_OF_RANGE,
                        format!("{} = {} is not a valid {}", $field, value, stringify!($name)),
                    )),
                }
            }
            /// The manual's numeric value.
            pub fn raw(self) -> u32 {
                self as u32
            }
        }
    };
}
pub use raw_enum;

raw_enum! {
    /// `MC_BufferMode` (§3.6).
    BufferMode: "BufferMode" {
        /// MC_Aborting (0, default): start at once, abort the running and buffered commands.
        #[default]
        Aborting = 0,
        /// MC_Buffered (1): start when the running command has finished (velocity 0).
        Buffered = 1,
        /// MC_BlendingLow (2): transition at the end position with min(v1, v2).
        BlendingLow = 2,
        /// MC_BlendingPrevious (3): transition with v1.
        BlendingPrevious = 3,
        /// MC_BlendingNext (4): transition with v2.
        BlendingNext = 4,
        /// MC_BlendingHigh (5): transition with max(v1, v2).
        BlendingHigh = 5,
    }
}

raw_enum! {
    /// `MC_Direction` (§5.3).
    Direction: "Direction" {
        /// MC_Positive_Direction (1, default of MC_MoveVelocity).
        #[default]
        Positive = 1,
        /// MC_Shortest_Way (2).
        ShortestWay = 2,
        /// MC_Negative_Direction (3).
        Negative = 3,
        /// MC_Current_Direction (4).
        Current = 4,
        /// MC_Undefined_Direction (128).
        Undefined = 128,
    }
}

raw_enum! {
    /// `E_JogMode` (§4.11).
    JogMode: "Mode" {
        /// MC_JOGMODE_STANDARD_SLOW (0).
        #[default]
        StandardSlow = 0,
        /// MC_JOGMODE_STANDARD_FAST (1).
        StandardFast = 1,
        /// MC_JOGMODE_CONTINOUS (2) (Beckhoff's spelling).
        Continous = 2,
        /// MC_JOGMODE_INCHING (3).
        Inching = 3,
        /// MC_JOGMODE_INCHING_MODULO (4).
        InchingModulo = 4,
    }
}

raw_enum! {
    /// `MC_HomingMode` (§4.10).
    HomingMode: "HomingMode" {
        /// MC_DefaultHoming (0): homing run.
        #[default]
        DefaultHoming = 0,
        /// MC_Direct (1): set the position without motion.
        Direct = 1,
        /// MC_ForceCalibration (2): set the calibrated flag.
        ForceCalibration = 2,
        /// MC_ResetCalibration (3): clear the calibrated flag.
        ResetCalibration = 3,
    }
}

raw_enum! {
    /// `E_SuperpositionMode` (§4.9.1); the spellings VEOREDUCTION/VELREDUCTION of the manual
    /// are the same values.
    SuperpositionMode: "Mode" {
        /// SUPERPOSITIONMODE_VELOREDUCTION_ADDITIVEMOTION (1).
        #[default]
        VeloReductionAdditiveMotion = 1,
        /// SUPERPOSITIONMODE_VELOREDUCTION_LIMITEDMOTION (2).
        VeloReductionLimitedMotion = 2,
        /// SUPERPOSITIONMODE_LENGTHREDUCTION_ADDITIVEMOTION (3).
        LengthReductionAdditiveMotion = 3,
        /// SUPERPOSITIONMODE_LENGTHREDUCTION_LIMITEDMOTION (4).
        LengthReductionLimitedMotion = 4,
        /// SUPERPOSITIONMODE_ACCREDUCTION_ADDITIVEMOTION (5).
        AccReductionAdditiveMotion = 5,
        /// SUPERPOSITIONMODE_ACCREDUCTION_LIMITEDMOTION (6).
        AccReductionLimitedMotion = 6,
    }
}

raw_enum! {
    /// `E_SuperpositionAbortOption` (§4.9.1).
    SuperpositionAbortOption: "AbortOption" {
        /// SUPERPOSITIONOPTION_ABORTATSTANDSTILL (0, default).
        #[default]
        AbortAtStandstill = 0,
        /// SUPERPOSITIONOPTION_RESUMEAFTERSTANDSTILL (1).
        ResumeAfterStandstill = 1,
        /// SUPERPOSITIONOPTION_RESUMEAFTERMOTIONSTOP (2).
        ResumeAfterMotionStop = 2,
    }
}

raw_enum! {
    /// `E_TouchProbe` (§5.3): the latch unit.
    TouchProbeUnit: "TouchProbe" {
        /// TouchProbe1 (1).
        #[default]
        TouchProbe1 = 1,
        /// TouchProbe2 (2).
        TouchProbe2 = 2,
        /// TouchProbe3 (3, not available).
        TouchProbe3 = 3,
        /// TouchProbe4 (4, not available).
        TouchProbe4 = 4,
        /// PlcEvent (10): a plain PLC signal, cycle resolution.
        PlcEvent = 10,
    }
}

raw_enum! {
    /// `E_SignalEdge` (§5.3).
    SignalEdge: "Edge" {
        /// RisingEdge (0).
        #[default]
        RisingEdge = 0,
        /// FallingEdge (1).
        FallingEdge = 1,
    }
}

raw_enum! {
    /// `E_TouchProbeMode` (§5.3).
    TouchProbeMode: "Mode" {
        /// TOUCHPROBEMODE_SINGLE_COMPATIBILITYMODE (0).
        SingleCompatibilityMode = 0,
        /// TOUCHPROBEMODE_SINGLE (1).
        #[default]
        Single = 1,
        /// TOUCHPROBEMODE_CONTINOUS (2).
        Continous = 2,
    }
}
