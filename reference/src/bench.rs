//! `reference bench`: figures, not pass/fail (issue 11, `docs/performance.md`).
//!
//! Part of the binary only: it owns the counting allocator that measures peak
//! heap bytes, which must be the program's global allocator.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use halfedge::{DVec3, EdgeId, Mesh};
use reference::solution::{self, Weights};

/// The system allocator, counting the bytes in use and their peak. Two
/// relaxed atomic additions per call: nothing next to the allocation itself.
/// Large blocks are faulted in as they are handed out (see [`prefault`]).
pub struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(bytes: usize) {
    let now = IN_USE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

/// Blocks (or a block's grown part) at least this large are faulted in at
/// once: the mesh's arenas and the subdivision's lists, not small values.
const PREFAULT_BYTES: usize = 1 << 20;

/// Whether [`prefault`] acts: off unless `bench` (without `--no-prefault`)
/// or `subdivide`'s rounds turn it on, where the reference subdivides large
/// meshes itself. Never in `serve-case`, the child the grader caps and
/// times as it does a student's (page by page), nor for output text.
static PREFAULT: AtomicBool = AtomicBool::new(false);

pub fn set_prefault(on: bool) {
    PREFAULT.store(on, Ordering::Relaxed);
}

/// Faults in the whole pages of `block[from..to]` with one
/// `madvise(MADV_POPULATE_WRITE)`, in address order, instead of one trap
/// per 4 KiB page when each is first written. The subdivision reserves its
/// arenas exactly (`solution::reserve_round`), so every page faulted in
/// here is written soon after; a block reserved far beyond its use would
/// only hold its memory sooner. What it is worth, and why it is kept:
/// `docs/performance.md` (`bench --no-prefault` measures it). Kernels
/// before 5.14 refuse the advice: that, like any error, only leaves the
/// pages to fault in one by one as before.
fn prefault(block: *mut u8, from: usize, to: usize) {
    if to - from < PREFAULT_BYTES || !PREFAULT.load(Ordering::Relaxed) {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        // Whole pages of the block only; a grown block's new part starts
        // inside a page that is the block's own, so that page is included.
        let first = (block as usize).div_ceil(PAGE) * PAGE;
        let start = ((block as usize + from) / PAGE * PAGE).max(first);
        let end = (block as usize + to) / PAGE * PAGE;
        if end <= start {
            return;
        }
        // SAFETY: [start, end) lies inside a block the allocator has just
        // handed out, and the advice only faults its pages in (their
        // contents, zero or already written, are kept).
        unsafe {
            libc::madvise(
                start as *mut libc::c_void,
                end - start,
                libc::MADV_POPULATE_WRITE,
            )
        };
    }
}

fn shrank(bytes: usize) {
    IN_USE.fetch_sub(bytes, Ordering::Relaxed);
}

// SAFETY: every call is forwarded unchanged to `System`; only counters change,
// and large blocks get `prefault`'s advice, which keeps their contents.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            prefault(p, 0, layout.size());
            grew(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            prefault(p, 0, layout.size());
            grew(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        shrank(layout.size());
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size > layout.size() {
                // The new part only: the part kept holds what was written.
                prefault(p, layout.size(), new_size);
            }
            // A moving realloc holds both blocks for a moment: count that,
            // since the machine must hold them too.
            if p != ptr {
                grew(new_size);
                shrank(layout.size());
            } else if new_size >= layout.size() {
                grew(new_size - layout.size());
            } else {
                shrank(layout.size() - new_size);
            }
        }
        p
    }
}

/// Heap bytes in use now.
fn in_use() -> usize {
    IN_USE.load(Ordering::Relaxed)
}

/// Starts a new peak from what is in use now.
fn reset_peak() {
    PEAK.store(in_use(), Ordering::Relaxed);
}

fn peak() -> usize {
    PEAK.load(Ordering::Relaxed)
}

/// What `bench` measures.
pub struct Options {
    /// Timed runs of every figure.
    pub runs: usize,
    /// Icosphere levels to subdivide.
    pub levels: Vec<usize>,
    /// Include the 200 x 100 torus.
    pub torus: bool,
    /// Where the input meshes are written as OBJ.
    pub obj_dir: PathBuf,
    /// Time full grades of the reference.
    pub grade: bool,
    /// Time edit -> verdict with the student's debug build.
    pub edit: bool,
}

/// Median and spread of several runs, in seconds.
struct Stats {
    median: f64,
    min: f64,
    max: f64,
}

impl Stats {
    fn of(mut times: Vec<f64>) -> Stats {
        times.sort_by(f64::total_cmp);
        Stats {
            median: times[times.len() / 2],
            min: times[0],
            max: times[times.len() - 1],
        }
    }
    /// `median [min-max]` in milliseconds.
    fn ms(&self) -> String {
        format!(
            "{:.2} [{:.2}-{:.2}]",
            self.median * 1e3,
            self.min * 1e3,
            self.max * 1e3
        )
    }
    /// `median [min-max]` in seconds.
    fn s(&self) -> String {
        format!("{:.3} [{:.3}-{:.3}]", self.median, self.min, self.max)
    }
}

/// The CPU time this thread has used, in seconds: unlike the wall clock it
/// does not count time spent waiting for a core another program holds.
fn cpu_now() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec, which `ts` is.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The lab's phases, timed one by one (the body of
/// `solution::loop_subdivide_with`, with a clock between the steps).
const PHASES: [&str; 5] = ["vertex", "edge", "split", "flip", "move"];

fn subdivide_in_phases(mesh: &mut Mesh, times: &mut [f64; 5]) {
    let mut clock = cpu_now();
    let mut lap = |i: usize, times: &mut [f64; 5]| {
        let now = cpu_now();
        times[i] += now - clock;
        clock = now;
    };
    solution::vertex_points(mesh, Weights::Warren);
    lap(0, times);
    solution::edge_points(mesh);
    lap(1, times);
    solution::reserve_round(mesh);
    let old: Vec<EdgeId> = mesh.edge_ids().collect();
    let old_new = solution::split_edges(mesh, &old, solution::split_edge);
    drop(old);
    lap(2, times);
    solution::flip_listed(mesh, &old_new, solution::flip_edge);
    lap(3, times);
    solution::move_vertices(mesh);
    lap(4, times);
}

/// One input mesh of the bench.
struct Input {
    name: String,
    file: String,
    mesh: Mesh,
}

fn inputs(options: &Options) -> Vec<Input> {
    let mut out: Vec<Input> = options
        .levels
        .iter()
        .map(|&level| Input {
            name: format!("icosphere({level})"),
            file: format!("icosphere-{level}.obj"),
            mesh: halfedge::shapes::icosphere(level),
        })
        .collect();
    if options.torus {
        out.push(Input {
            name: "torus(200x100)".into(),
            file: "torus-200x100.obj".into(),
            mesh: halfedge::shapes::torus(200, 100, 1.0, 0.3),
        });
    }
    out
}

/// What this machine is, as far as a reader of the figures needs.
fn machine() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let profile = if cfg!(debug_assertions) {
        "DEBUG build: figures mean little, run with --release"
    } else {
        "release build"
    };
    format!(
        "{model}, {cores} cores available, {} {}; {profile}",
        std::env::consts::OS,
        std::env::consts::ARCH
    )
}

pub fn run(options: &Options) -> Result<ExitCode, String> {
    let runs = options.runs;
    println!("machine: {}", machine());
    println!(
        "each figure: median [min-max] of {runs} runs, one thread; rates and ns/face from the \
         thread's CPU time (steadier than the wall clock on a shared machine); peak bytes from \
         a counting allocator (the mesh's own arenas and every temporary, per output face)"
    );

    let inputs = inputs(options);
    std::fs::create_dir_all(&options.obj_dir)
        .map_err(|e| format!("{}: {e}", options.obj_dir.display()))?;
    for input in &inputs {
        let path = options.obj_dir.join(&input.file);
        input
            .mesh
            .write_obj_file(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    println!(
        "input meshes written as OBJ to {} (feed the same files to other libraries)",
        options.obj_dir.display()
    );

    println!();
    println!("building from indexed faces (Mesh::from_faces)");
    println!(
        "{:<16} {:>9} {:>9} {:>24} {:>9} {:>12}",
        "mesh", "vertices", "faces", "wall ms", "cpu ms", "M faces/s"
    );
    for input in &inputs {
        let (positions, faces) = input.mesh.to_faces();
        let times: Vec<(f64, f64)> = (0..runs).map(|_| time_build(&positions, &faces)).collect();
        let wall = Stats::of(times.iter().map(|t| t.0).collect());
        let cpu = Stats::of(times.iter().map(|t| t.1).collect());
        println!(
            "{:<16} {:>9} {:>9} {:>24} {:>9.2} {:>12.2}",
            input.name,
            positions.len(),
            faces.len(),
            wall.ms(),
            cpu.median * 1e3,
            faces.len() as f64 / cpu.median / 1e6
        );
    }

    for rounds in [1, 2] {
        println!();
        println!(
            "loop_subdivide, {rounds} round{}",
            if rounds == 1 { "" } else { "s" }
        );
        println!(
            "{:<16} {:>10} {:>24} {:>8} {:>10} {:>8} {:>8}   phases, cpu ms: {}",
            "mesh",
            "out faces",
            "wall ms",
            "cpu ms",
            "M faces/s",
            "ns/face",
            "B/face",
            PHASES.join(" / ")
        );
        for input in &inputs {
            let row = time_subdivide(&input.mesh, rounds, runs);
            println!(
                "{:<16} {:>10} {:>24} {:>8.2} {:>10.2} {:>8.1} {:>8.0}   {}",
                input.name,
                row.faces,
                row.total.ms(),
                row.cpu * 1e3,
                row.faces as f64 / row.cpu / 1e6,
                row.cpu * 1e9 / row.faces as f64,
                row.peak_bytes as f64 / row.faces as f64,
                row.phases
                    .iter()
                    .map(|t| format!("{:.1}", t * 1e3))
                    .collect::<Vec<_>>()
                    .join(" / ")
            );
        }
    }

    if options.grade {
        println!();
        grade_figures(runs)?;
    }
    if options.edit {
        println!();
        edit_to_verdict(runs)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// Wall and CPU seconds of one build.
fn time_build(positions: &[DVec3], faces: &[Vec<usize>]) -> (f64, f64) {
    let (start, cpu) = (Instant::now(), cpu_now());
    let mesh = Mesh::from_faces(positions, faces).expect("a generated mesh builds");
    let t = (start.elapsed().as_secs_f64(), cpu_now() - cpu);
    drop(mesh);
    t
}

struct Row {
    faces: usize,
    total: Stats,
    /// Median CPU seconds of the rounds.
    cpu: f64,
    /// Median time of each phase, summed over the rounds, in seconds.
    phases: [f64; 5],
    /// The most heap in use during the rounds, above what was in use before
    /// the input was copied: the mesh and every temporary.
    peak_bytes: usize,
}

fn time_subdivide(input: &Mesh, rounds: usize, runs: usize) -> Row {
    let mut totals = Vec::new();
    let mut cpus = Vec::new();
    let mut faces = 0;
    let mut peak_bytes = 0;
    for _ in 0..runs {
        let before = in_use();
        let mut mesh = input.clone();
        reset_peak();
        let (start, cpu) = (Instant::now(), cpu_now());
        for _ in 0..rounds {
            solution::loop_subdivide(&mut mesh);
        }
        cpus.push(cpu_now() - cpu);
        totals.push(start.elapsed().as_secs_f64());
        peak_bytes = peak_bytes.max(peak() - before);
        faces = mesh.num_real_faces();
    }
    let mut phase_runs: Vec<[f64; 5]> = Vec::new();
    for _ in 0..runs {
        let mut mesh = input.clone();
        let mut times = [0.0; 5];
        for _ in 0..rounds {
            subdivide_in_phases(&mut mesh, &mut times);
        }
        phase_runs.push(times);
    }
    let mut phases = [0.0; 5];
    for (i, p) in phases.iter_mut().enumerate() {
        *p = Stats::of(phase_runs.iter().map(|t| t[i]).collect()).median;
    }
    Row {
        faces,
        total: Stats::of(totals),
        cpu: Stats::of(cpus).median,
        phases,
        peak_bytes,
    }
}

/// Target of a full warm grade of the reference (issue 20), seconds.
const GRADE_TARGET: f64 = 0.5;

/// The seed of the fresh cases in the timed grade: any seed makes the same
/// number of cases of the same kinds; a fixed one keeps runs comparable.
const GRADE_FRESH_SEED: u64 = 0x0000_0000_0000_0001;

/// Full grades of the reference as one submission is graded in a class:
/// every case of `lab/`, `bonus/` and `hidden/`, plus one seed's fresh
/// cases, each in its locked-in child, every labelling (warm: the
/// programs are built). The cases and child runs counted are the grader's
/// own (its JSON), so the line says exactly what was timed.
fn grade_figures(runs: usize) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let fixtures = reference::lab_root().join("fixtures");
    // The fresh cases are told apart by the names they were written under.
    let (with_fresh, fresh) = reference::class::fixtures_with_fresh(&fixtures, GRADE_FRESH_SEED)?;
    let mut times = Vec::new();
    let mut counted = GradeCount::default();
    for _ in 0..runs {
        let start = Instant::now();
        let out = Command::new(&exe)
            .args(["grade", "--bonus", "--format", "json", "--fixtures"])
            .arg(with_fresh.path())
            .stderr(Stdio::null())
            .output()
            .map_err(|e| e.to_string())?;
        times.push(start.elapsed().as_secs_f64());
        if !out.status.success() {
            return Err("the reference did not pass its own grade".into());
        }
        let json: serde_json::Value =
            serde_json::from_slice(&out.stdout).map_err(|e| format!("the grader's JSON: {e}"))?;
        counted = GradeCount::of(&json, &fresh);
    }
    if counted.fresh == 0 || counted.sequence == 0 {
        return Err(format!(
            "the timed grade ran {} fresh and {} sequence cases: it must run both",
            counted.fresh, counted.sequence
        ));
    }
    let stats = Stats::of(times);
    println!(
        "full warm grade of the reference, as a class grades one submission ({} cases: {} lab, \
         {} bonus, {} hidden; {} of them fresh, seed {GRADE_FRESH_SEED:016x}, and {} \
         sequences; {} calls with every labelling, one locked-in child per case): {} s \
         (target {GRADE_TARGET:.1} s: {})",
        counted.cases,
        counted.lab,
        counted.bonus,
        counted.hidden,
        counted.fresh,
        counted.sequence,
        counted.runs,
        stats.s(),
        if stats.median <= GRADE_TARGET {
            "met"
        } else {
            "not met"
        }
    );
    Ok(())
}

/// What a grade ran, from the grader's JSON report.
#[derive(Default)]
struct GradeCount {
    cases: usize,
    lab: usize,
    bonus: usize,
    hidden: usize,
    fresh: usize,
    sequence: usize,
    runs: u64,
}

impl GradeCount {
    /// `fresh`: the names of the fresh cases added to the fixtures.
    fn of(json: &serde_json::Value, fresh: &[String]) -> GradeCount {
        let cases = json["cases"].as_array().map(Vec::as_slice).unwrap_or(&[]);
        let is = |c: &serde_json::Value, key: &str, value: &str| c[key].as_str() == Some(value);
        let count = |key: &str, value: &str| cases.iter().filter(|c| is(c, key, value)).count();
        GradeCount {
            cases: cases.len(),
            lab: count("group", "lab"),
            bonus: count("group", "bonus"),
            hidden: count("group", "hidden"),
            fresh: cases
                .iter()
                .filter(|c| {
                    c["name"]
                        .as_str()
                        .is_some_and(|n| fresh.iter().any(|f| f == n))
                })
                .count(),
            sequence: count("stage", "sequence"),
            runs: json["plan"]["runs"].as_u64().unwrap_or(0),
        }
    }
}

/// Targets of the student's loop (issue 20): edit -> verdict on the stubs
/// and on a correct solution, seconds.
const EDIT_TARGET_STUBS: f64 = 1.0;
const EDIT_TARGET_CORRECT: f64 = 1.2;

/// A student's edit -> verdict: the student's file is touched (so cargo
/// rebuilds it as after an edit) and `cargo run -p grader` runs to its
/// verdict, in the dev profile students use. Twice, in a handout copy of
/// the lab (the grader refuses to compile `crates/meshedit` beside the
/// hidden cases, so the lab itself gives no verdict to time): the stubs as
/// handed out, then the model solution pasted in as a student's correct
/// answer. Its build is in `target/bench-edit`, kept between runs; one
/// untimed run first builds everything else.
fn edit_to_verdict(runs: usize) -> Result<(), String> {
    let root = reference::lab_root();
    let scratch = reference::handout::private_temp_dir("meshlab-bench-edit-")?;
    let copy = scratch.path().join("lab");
    reference::handout::copy_lab(&root, &copy, reference::handout::Purpose::Handout)?;
    let target = root.join("target/bench-edit");
    let stubs = time_edits(&copy, &target, runs)?;
    print_edit("the handout's stubs", &stubs, EDIT_TARGET_STUBS);

    let pasted = copy.join("crates/meshedit/src/lib.rs");
    std::fs::write(&pasted, include_str!("solution.rs"))
        .map_err(|e| format!("{}: {e}", pasted.display()))?;
    let correct = time_edits(&copy, &target, runs);
    drop(scratch);
    print_edit(
        "a correct solution (the model's, pasted in)",
        &correct?,
        EDIT_TARGET_CORRECT,
    );
    Ok(())
}

fn print_edit(what: &str, times: &Stats, target: f64) {
    println!(
        "edit -> verdict, {what} (touch crates/meshedit/src/lib.rs, `cargo run -p grader`, \
         dev profile: rebuild, link, grade): {} s (target {target:.1} s: {})",
        times.s(),
        if times.median <= target {
            "met"
        } else {
            "not met"
        }
    );
}

/// Times `runs` edits of `lab`'s student file, each followed by `cargo run
/// -p grader` to its verdict, after one untimed run.
fn time_edits(lab: &Path, target_dir: &Path, runs: usize) -> Result<Stats, String> {
    let student = lab.join("crates/meshedit/src/lib.rs");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let grade = |quiet_build: bool| -> Result<f64, String> {
        touch(&student)?;
        let start = Instant::now();
        let mut command = Command::new(&cargo);
        command
            .current_dir(lab)
            .args(["run", "--quiet", "-p", "grader", "--target-dir"])
            .arg(target_dir)
            .stdout(Stdio::null());
        if quiet_build {
            command.stderr(Stdio::null());
        }
        let status = command
            .status()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        // Passed (0) or failed (1), only the time matters; anything else
        // (a refusal, a build error) is no verdict, and its time no figure.
        match status.code() {
            Some(0 | 1) => Ok(start.elapsed().as_secs_f64()),
            _ => Err(format!(
                "`cargo run -p grader` in {} gave no verdict ({status}); run it there to see why",
                lab.display()
            )),
        }
    };
    eprintln!(
        "edit -> verdict: building the student's debug programs in {} once (untimed)...",
        lab.display()
    );
    grade(false)?;
    let times = (0..runs)
        .map(|_| grade(true))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Stats::of(times))
}

/// Sets a file's modification time to now, as saving it in an editor does.
fn touch(path: &Path) -> Result<(), String> {
    let file = std::fs::File::options()
        .append(true)
        .open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    file.set_modified(std::time::SystemTime::now())
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// `bench --peers`: writes the icospheres of `levels` as OBJ into `dir`, the
/// files `reference/bench/peers/run.sh` gives every library.
pub fn write_peer_inputs(levels: &[usize], dir: &Path) -> Result<ExitCode, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for &level in levels {
        let path = dir.join(format!("icosphere-{level}.obj"));
        halfedge::shapes::icosphere(level)
            .write_obj_file(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        println!("{}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The CPU time of the whole process, in milliseconds, as the peers' drivers
/// read it (`CLOCK_PROCESS_CPUTIME_ID`: every thread, should one start any).
fn process_cpu_ms() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec, which `ts` is.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 * 1e3 + ts.tv_nsec as f64 * 1e-6
}

/// The most memory this process has held in RAM, in kB (`ru_maxrss`).
fn max_rss_kb() -> i64 {
    // SAFETY: getrusage writes one rusage, which `usage` is; zeroed is a
    // valid value of that plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) };
    usage.ru_maxrss
}

/// `bench --peers --peer-obj FILE --rounds N`: the reference's driver in the
/// peers' comparison. Reads `file` (not timed), then times `rounds` calls of
/// `solution::loop_subdivide`, once, and prints the line every driver prints
/// (`wall_ms= cpu_ms= faces= maxrss_kb=`) plus the peak heap bytes per
/// output face.
pub fn peer_run(file: &Path, rounds: usize) -> Result<ExitCode, String> {
    // As `bench` counts: the peak above what was in use before the input
    // mesh existed, so the mesh itself and every temporary.
    let before = in_use();
    let mut mesh = Mesh::from_obj_file(file).map_err(|e| format!("{}: {e}", file.display()))?;
    reset_peak();
    let (start, cpu) = (Instant::now(), process_cpu_ms());
    for _ in 0..rounds {
        solution::loop_subdivide(&mut mesh);
    }
    let cpu = process_cpu_ms() - cpu;
    let wall = start.elapsed().as_secs_f64() * 1e3;
    let faces = mesh.num_real_faces();
    println!(
        "wall_ms={wall:.3} cpu_ms={cpu:.3} faces={faces} maxrss_kb={} heap_b_per_face={:.0}",
        max_rss_kb(),
        (peak() - before) as f64 / faces as f64
    );
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::GradeCount;

    /// The fraction of the whole pages of `v`'s allocation (its capacity,
    /// written or not) that are in memory (`mincore`).
    #[cfg(target_os = "linux")]
    fn resident(v: &Vec<u8>) -> f64 {
        const PAGE: usize = 4096;
        let start = (v.as_ptr() as usize).div_ceil(PAGE) * PAGE;
        let end = (v.as_ptr() as usize + v.capacity()) / PAGE * PAGE;
        let mut pages = vec![0u8; (end - start) / PAGE];
        // SAFETY: [start, end) lies in `v`'s allocation; mincore writes
        // one byte per page into `pages`, which has that many.
        let r =
            unsafe { libc::mincore(start as *mut libc::c_void, end - start, pages.as_mut_ptr()) };
        assert_eq!(r, 0, "mincore: {}", std::io::Error::last_os_error());
        pages.iter().filter(|&&p| p & 1 == 1).count() as f64 / pages.len() as f64
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn prefault_puts_a_large_block_in_memory_before_it_is_written() {
        // 64 MiB: above glibc's largest mmap threshold, so each block is a
        // fresh mapping, never touched memory reused from the heap.
        const SIZE: usize = 64 << 20;
        super::set_prefault(false);
        let plain: Vec<u8> = Vec::with_capacity(SIZE);
        super::set_prefault(true);
        let faulted: Vec<u8> = Vec::with_capacity(SIZE);
        let mut grown: Vec<u8> = Vec::with_capacity(2 << 20);
        grown.reserve_exact(SIZE);
        super::set_prefault(false);
        let (plain, faulted, grown) = (resident(&plain), resident(&faulted), resident(&grown));
        if faulted < 1.0 && std::env::var_os("CI").is_none() {
            // Kernels before 5.14 refuse MADV_POPULATE_WRITE.
            eprintln!("skipped: this kernel did not fault the block in ({faulted:.2} resident)");
            return;
        }
        assert!(
            plain < 0.5,
            "a block without the advice is {plain:.2} resident already"
        );
        assert_eq!(faulted, 1.0, "a block with the advice");
        assert_eq!(grown, 1.0, "a block grown with the advice");
    }

    #[test]
    fn a_grade_is_counted_by_group_stage_and_the_fresh_cases_added() {
        let json = serde_json::json!({
            "plan": {"runs": 12},
            "cases": [
                {"name": "cube-flip-1", "group": "lab", "stage": "flip"},
                {"name": "cube-sequence-1", "group": "lab", "stage": "sequence"},
                {"name": "tube-split-1", "group": "bonus", "stage": "split"},
                {"name": "fresh-1-torus-flip", "group": "hidden", "stage": "flip"},
                {"name": "fresh-1-tube-split", "group": "bonus", "stage": "split"},
                {"name": "cone-5-flip-1", "group": "hidden", "stage": "flip"},
                // Named like a fresh case, but not one of those added.
                {"name": "fresh-2-torus-subdivide", "group": "hidden", "stage": "subdivide"},
            ]
        });
        let fresh = [
            "fresh-1-torus-flip".to_string(),
            "fresh-1-tube-split".to_string(),
        ];
        let c = GradeCount::of(&json, &fresh);
        assert_eq!(
            (c.cases, c.lab, c.bonus, c.hidden, c.fresh, c.sequence, c.runs),
            (7, 2, 2, 3, 2, 1, 12)
        );
    }

    #[test]
    fn a_report_without_cases_counts_nothing() {
        let c = GradeCount::of(&serde_json::json!({"error": "no fixtures"}), &[]);
        assert_eq!((c.cases, c.fresh, c.sequence, c.runs), (0, 0, 0, 0));
    }
}
