//! `fixtures`: regenerate `fixtures/` from the reference, or check it.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use reference::render;
use reference::solution::Weights;

use super::{fixtures_dir, Outcome, Weighting};

#[derive(clap::Args)]
pub struct Args {
    /// Write nothing; exit 1 naming every file that is stale or missing.
    #[arg(long)]
    check: bool,
    /// The fixtures folder [default: the lab's fixtures/].
    #[arg(long, value_name = "DIR")]
    dir: Option<PathBuf>,
    #[command(flatten)]
    weights: Weighting,
}

pub fn run(args: Args) -> Outcome {
    let weights = args.weights.weights();
    write(&fixtures_dir(args.dir), args.check, weights)
}

fn write(root: &Path, check: bool, weights: Weights) -> Outcome {
    let files = render::render_all(root, weights)?;
    let mut stale = Vec::new();
    for (rel, text) in &files {
        let path = root.join(rel);
        let now = std::fs::read_to_string(&path).ok();
        if now.as_deref() == Some(text.as_str()) {
            continue;
        }
        let what = if now.is_none() { "missing" } else { "stale" };
        if check {
            stale.push(format!("{what}: {}", path.display()));
        } else {
            std::fs::create_dir_all(path.parent().expect("a group folder"))
                .map_err(|e| e.to_string())?;
            std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
            stale.push(format!("wrote {}", path.display()));
        }
    }
    for line in &stale {
        println!("{line}");
    }
    if check && !stale.is_empty() {
        println!(
            "{} of {} fixtures are out of date: run `cargo run -p reference -- fixtures`",
            stale.len(),
            files.len()
        );
        return Ok(ExitCode::from(1));
    }
    if check {
        println!("{} fixtures, all up to date", files.len());
    } else {
        println!(
            "{} fixtures, {} written, the rest unchanged",
            files.len(),
            stale.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}
