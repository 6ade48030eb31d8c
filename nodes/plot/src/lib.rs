//! `motion_plot`: figures of a recorded run (issue 14 item 5). [`run`] reads an MCAP
//! recording of the ROS 2 profile (what `motion_launch --record` and `ros2 bag record -s mcap`
//! write) into series, recognising channels by their message type; [`figures`] draws them
//! with `plotters` as PNG and SVG. Knows nothing of nodes, DDS or engines.

pub mod figures;
pub mod run;

pub use figures::render;
pub use run::{ReadError, Run};

/// Registers the font the figures write with (`sans-serif`): the first of `candidates` that
/// exists and loads, else DejaVu Sans where Debian puts it (package fonts-dejavu-core).
pub fn register_font(candidates: &[std::path::PathBuf]) -> Result<std::path::PathBuf, String> {
    let default = std::path::PathBuf::from("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf");
    for path in candidates.iter().chain(std::iter::once(&default)) {
        let Ok(bytes) = std::fs::read(path) else {
            continue;
        };
        // The font lives as long as the process draws.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        if plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, bytes)
            .is_ok()
        {
            return Ok(path.clone());
        }
    }
    Err(format!(
        "no usable font: tried {:?} and {} (install fonts-dejavu-core or pass --font FILE.ttf)",
        candidates,
        default.display()
    ))
}
