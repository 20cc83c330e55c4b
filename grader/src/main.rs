//! The grader (filled in by the grader issue).

fn main() {
    eprintln!("the grader is not built yet");
    std::process::exit(2);
}
