//! `motion_plot RUN.mcap [--out DIR] [--font FILE.ttf]`: PNG and SVG figures of a recorded
//! run (default DIR: `RUN_plots/` next to the file). Exit code 2 for bad arguments or an
//! unreadable recording.

use std::path::PathBuf;

fn main() {
    std::process::exit(run());
}

fn run() -> i32 {
    let usage = "usage: motion_plot RUN.mcap [--out DIR] [--font FILE.ttf]";
    let mut args = std::env::args().skip(1);
    let (mut file, mut out, mut fonts) = (None, None, Vec::new());
    while let Some(a) = args.next() {
        match a.as_str() {
            "--out" => out = args.next().map(PathBuf::from),
            "--font" => fonts.extend(args.next().map(PathBuf::from)),
            "-h" | "--help" => {
                println!("{usage}");
                return 0;
            }
            s if s.starts_with('-') => {
                eprintln!("unknown option {s}\n{usage}");
                return 2;
            }
            s => file = Some(PathBuf::from(s)),
        }
    }
    let Some(file) = file else {
        eprintln!("{usage}");
        return 2;
    };
    let out = out.unwrap_or_else(|| {
        let stem = file.file_stem().unwrap_or_default().to_string_lossy();
        file.with_file_name(format!("{stem}_plots"))
    });
    if let Err(e) = motion_plot::register_font(&fonts) {
        eprintln!("motion_plot: {e}");
        return 2;
    }
    let bytes = match std::fs::read(&file) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("motion_plot: {}: {e}", file.display());
            return 2;
        }
    };
    let run = match motion_plot::Run::read(&bytes) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("motion_plot: {}: {e}", file.display());
            return 2;
        }
    };
    match motion_plot::render(&run, &out) {
        Ok(files) => {
            println!(
                "{}: {} messages, {} axes, {} movers, {} CA groups, {} nodes with cycle statistics, {} command events on the axes",
                file.display(),
                run.messages,
                run.axes.len(),
                run.movers.len(),
                run.gaps.len(),
                run.cycle_stats.len(),
                run.commands
                    .iter()
                    .filter(|c| run.axes.contains_key(&c.object))
                    .count()
            );
            for f in files {
                println!("{}", f.display());
            }
            0
        }
        Err(e) => {
            eprintln!("motion_plot: drawing: {e}");
            1
        }
    }
}
