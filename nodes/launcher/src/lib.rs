//! `motion_launch`: runs the nodes of a launch config in one process, each with its own cycle.

use motion_runtime::NodeKind;

/// Every node kind of the suite.
pub const KINDS: &[NodeKind] = &[
    axis_node::NODE_KIND,
    planar_node::NODE_KIND,
    pickplace_node::NODE_KIND,
];
