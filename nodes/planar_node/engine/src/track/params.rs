//! Track init parameters that shape collision avoidance (xplanar.md §1.6, §5.6.4, §5.11):
//! "Maximal mover width/height", "Check collision against static objects", "Collision range
//! mode" and "Collision range at start/end".

use super::MoverDrive;
use super::TrackSystem;
use crate::config::{CollisionRangeMode, TrackConfig};
use crate::errors::{reject, E_INVALID_STATE};
use crate::types::PlanarState;
use crate::PlanarReply;
use motion_core::Rejection;

/// The collision parameters of one track.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TrackParams {
    /// Maximal mover width \[mm\].
    pub max_mover_width: f64,
    /// Maximal mover height \[mm\].
    pub max_mover_height: f64,
    /// AddToGroup checks the tube against the stator area and other member tracks.
    pub check_static_collision: bool,
    pub range_mode: CollisionRangeMode,
    /// Manual ranges at start / end \[mm\].
    pub manual_start: f64,
    pub manual_end: f64,
}

impl TrackParams {
    pub fn of(t: &TrackConfig) -> Self {
        TrackParams {
            max_mover_width: t.max_mover_width,
            max_mover_height: t.max_mover_height,
            check_static_collision: t.check_static_collision,
            range_mode: t.collision_range_mode,
            manual_start: t.collision_range_start,
            manual_end: t.collision_range_end,
        }
    }

    /// R of §5.6.4: half the diagonal of the maximal mover \[mm\].
    pub fn mover_radius(&self) -> f64 {
        0.5 * self.max_mover_width.hypot(self.max_mover_height)
    }

    /// Distance beyond which a mover on this track no longer matters at a switch (automatic
    /// range) \[mm\]. The spec's proposal is 2R; it is enlarged to 2·√2·R + 50 mm so that the
    /// no-overlap guard's envelopes (axis-aligned squares of a rotating mover plus its stop
    /// range) of movers on different branches cannot touch either: a larger range only makes
    /// movers wait earlier (measured: with 2R the merge tests end in E_COLLISION). For the
    /// default 155 × 155 mm mover this is 360 mm.
    pub fn switch_clearance(&self) -> f64 {
        2.0 * std::f64::consts::SQRT_2 * self.mover_radius() + 50.0
    }

    /// Half-width of the track's tube in a group (§5.11): half the larger mover side, so a
    /// mover turned with the track heading stays inside \[mm\].
    pub fn tube_half_width(&self) -> f64 {
        0.5 * self.max_mover_width.max(self.max_mover_height)
    }

    /// The range at the start: the manual value in Manual mode, else `automatic`.
    pub fn range_start(&self, automatic: f64) -> f64 {
        match self.range_mode {
            CollisionRangeMode::Automatic => automatic,
            CollisionRangeMode::Manual => self.manual_start,
        }
    }

    /// The range at the end: the manual value in Manual mode, else `automatic`.
    pub fn range_end(&self, automatic: f64) -> f64 {
        match self.range_mode {
            CollisionRangeMode::Automatic => automatic,
            CollisionRangeMode::Manual => self.manual_end,
        }
    }
}

impl TrackSystem {
    /// TrackSetInitParameters: the §1.6 init parameters of track `k` from the fields of `p`
    /// (validated like the launch config), admissible while the track is Disabled. The switch
    /// ranges are recomputed by the caller (as after a geometry command).
    pub(crate) fn track_set_init_parameters(
        &mut self,
        objects: &mut dyn MoverDrive,
        k: usize,
        p: &TrackConfig,
    ) -> Result<PlanarReply, Rejection> {
        let who = self.track_who(k);
        if self.tracks[k].sm.state != PlanarState::Disabled {
            return Err(reject(
                E_INVALID_STATE,
                format!(
                    "{who}: init parameters can be set only while the track is Disabled (it is {:?})",
                    self.tracks[k].sm.state
                ),
            ));
        }
        p.check_init_params(&who).map_err(|e| Rejection {
            message: e.message.replacen("config ", "TrackSetInitParameters: ", 1),
            ..e
        })?;
        self.tracks[k].params = TrackParams::of(p);
        objects.done_now()
    }
}
