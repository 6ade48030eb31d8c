//! Time-optimal, jerk-limited trajectories shared by all engines (owned by the axis engine work).
