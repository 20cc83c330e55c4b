//! Attacks on the grader by a student who has read its source, each an
//! entry of the catalogue (`reference/src/catalogue/attacks.rs`) run through the real
//! binary, child processes and all.
//!
//! The attacks the grader stops are tested for the verdict, the message and
//! the attack's own report that it was denied. Those that still get
//! through are recorded as tests marked `#[ignore = "open: ..."]`: each
//! asserts what the grader should do, and fails today (run them with
//! `cargo test -p reference --test attacks -- --ignored`).

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::*;
use std::time::Duration;

use reference::catalogue::attacks;

impl Graded {
    fn context(&self) -> String {
        format!(
            "exit {} after {:?}\n{}\n--- stderr ---\n{}",
            self.code, self.took, self.stdout, self.stderr
        )
    }

    /// The attack's own line for `what`, e.g. `| attack: send by UDP: done`.
    fn attack(&self, what: &str) -> Option<&str> {
        self.stdout
            .lines()
            .find(|l| l.contains(&format!("| attack: {what}: ")))
    }

    fn denied(&self, what: &str) -> bool {
        self.attack(what).is_some_and(|l| l.contains(": denied ("))
    }

    fn warned(&self, text: &str) -> bool {
        self.stdout
            .lines()
            .any(|l| l.contains("[warn] ") && l.contains(text))
    }
}

/// Grades as an ordinary user, as a student or a TA on their own machine
/// does: as root, the grader itself runs as `nobody` (then its child runs
/// as the same user as the grader, as it would for anyone but root).
fn grade_as_user(implementation: &str, args: &[&str]) -> Graded {
    use std::os::unix::process::CommandExt;
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
    // SAFETY: geteuid only reads.
    if unsafe { libc::geteuid() } == 0 {
        cmd.uid(65534).gid(65534).current_dir("/");
    }
    grade_with(&mut cmd, implementation, args)
}

/// The Landlock ABI this kernel offers (0 when it has none).
fn landlock_abi() -> i64 {
    // SAFETY: landlock_create_ruleset(NULL, 0, VERSION) only reports the ABI.
    let abi = unsafe {
        libc::syscall(
            libc::SYS_landlock_create_ruleset,
            std::ptr::null::<u8>(),
            0usize,
            1u32,
        )
    };
    abi.max(0)
}

/// Processes still running an implementation's child (`serve-case NAME`),
/// with their process groups.
fn survivors(implementation: &str) -> Vec<(u32, i32)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(raw) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<&[u8]> = raw.split(|&b| b == 0).collect();
        if args.contains(&&b"serve-case"[..]) && args.contains(&implementation.as_bytes()) {
            // SAFETY: getpgid only reads.
            out.push((pid, unsafe { libc::getpgid(pid as i32) }));
        }
    }
    out
}

/// Kills what an attack left running, whole process groups at once (a
/// chain's levels share theirs), until nothing is left.
fn kill_survivors(implementation: &str) {
    for _ in 0..100 {
        let left = survivors(implementation);
        if left.is_empty() {
            return;
        }
        for (pid, pgid) in left {
            // SAFETY: signals to processes this test's attack started.
            unsafe {
                if pgid > 1 {
                    libc::kill(-pgid, libc::SIGKILL);
                }
                libc::kill(pid as i32, libc::SIGKILL);
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The verdict every attack that makes the no-flip mistake must get, from
/// a grader that survived it.
fn assert_no_flip_verdict(g: &Graded) {
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(
        g.stdout.contains("hint: no edge was flipped"),
        "{}",
        g.context()
    );
    assert!(
        g.stdout.trim_end().ends_with("[warn] test failed"),
        "{}",
        g.context()
    );
}

// ---------------------------------------------------------------------
// Stopped: the verdict is right and the attack reports it was denied.
// ---------------------------------------------------------------------

#[test]
fn odd_endings_and_forged_frames_are_named() {
    // (implementation, the warning it must get)
    let cases: &[(&str, &str)] = &[
        (
            "crafted-frame",
            "the result of subdivision is a invalid mesh: A face's halfedge was never set (or names no halfedge)! (f0)",
        ),
        ("hook-abort", "loop_subdivide crashed: signal 6 (SIGABRT: the program aborted)"),
        ("thread-overflow", "loop_subdivide overflowed the stack"),
        // A panic outside catch_unwind (the payload's drop) ends the program.
        ("payload-drop-panics", "loop_subdivide ended the program (exit status 101) before returning"),
        ("huge-mesh", "loop_subdivide returned a mesh far larger than any right answer"),
    ];
    for &(name, warning) in cases {
        let g = grade(name, &["--case", "cube-subdivide-1", "--timeout", "5"]);
        assert_eq!(g.code, 1, "{name}: {}", g.context());
        assert!(
            g.warned(warning),
            "{name}: expected {warning:?}\n{}",
            g.context()
        );
        assert!(
            g.stdout.trim_end().ends_with("[warn] test failed"),
            "{name}: {}",
            g.context()
        );
        assert!(!g.stderr.contains("panicked"), "{name}: {}", g.context());
    }
}

/// The labellings of a case share a child while their calls come back,
/// but a call that fails in a child that served an earlier one is run
/// again in a fresh child: a function right whenever it runs first in a
/// process passes, as it does when every call has a child of its own.
#[test]
fn state_left_by_an_earlier_call_decides_no_verdict() {
    let g = grade("later-calls-break", &["--case", "cube-subdivide-1"]);
    assert_eq!(g.code, 0, "{}", g.context());
    assert!(
        g.stdout.contains("lab cases passed: loop_subdivide 1/1"),
        "{}",
        g.context()
    );
    // And the mistake itself is seen where it is made on a first call.
    let g = grade("no-flip", &["--case", "cube-subdivide-1"]);
    assert_no_flip_verdict(&g);
}

#[test]
fn a_flood_of_output_is_cut_and_costs_no_time() {
    let g = grade("flood", &["--case", "cube-subdivide-1", "--timeout", "5"]);
    assert_no_flip_verdict(&g);
    assert!(g.stdout.contains("[... output cut ...]"), "{}", g.context());
    assert!(g.stdout.len() < 64 << 10, "{} bytes kept", g.stdout.len());
    assert!(g.took < Duration::from_secs(5), "{}", g.context());
}

#[test]
fn the_grader_cannot_be_signalled_traced_or_read() {
    // Signals out are refused by Landlock's scopes (ABI 6) or, as root, by
    // the child being `nobody`; elsewhere this attack would kill its job.
    let mut runs = Vec::new();
    if landlock_abi() >= 6 || is_root() {
        runs.push(grade("reach-parent", &["--case", "cube-subdivide-1"]));
    }
    // As the grader's own user, only Landlock stands in the way.
    if landlock_abi() >= 6 {
        runs.push(grade_as_user(
            "reach-parent",
            &["--case", "cube-subdivide-1"],
        ));
    }
    if runs.is_empty() {
        common::skip("no Landlock signal scoping and not root");
    }
    for g in runs {
        assert_no_flip_verdict(&g);
        for what in [
            "SIGKILL the grader",
            "SIGKILL the grader's process group",
            "ptrace the grader",
            "read the grader's memory",
            "open the grader's /proc/PID/mem",
        ] {
            assert!(g.denied(what), "{what}: {}", g.context());
        }
    }
}

/// Listeners for the `sockets` attack: what each received, if anything.
struct Listeners {
    udp: std::net::UdpSocket,
    tcp: std::net::TcpListener,
    unix: std::os::unix::net::UnixListener,
    abstract_unix: std::os::unix::net::UnixListener,
}

impl Listeners {
    fn open() -> Listeners {
        use std::os::linux::net::SocketAddrExt;
        use std::os::unix::fs::PermissionsExt;
        use std::os::unix::net::{SocketAddr, UnixListener};
        let _ = std::fs::remove_file(attacks::UNIX_SOCKET);
        let unix = UnixListener::bind(attacks::UNIX_SOCKET).unwrap();
        // Open to the child whatever user it runs as.
        std::fs::set_permissions(attacks::UNIX_SOCKET, std::fs::Permissions::from_mode(0o777))
            .unwrap();
        let name = SocketAddr::from_abstract_name(attacks::ABSTRACT_SOCKET).unwrap();
        let l = Listeners {
            udp: std::net::UdpSocket::bind(("127.0.0.1", attacks::UDP_PORT)).unwrap(),
            tcp: std::net::TcpListener::bind(("127.0.0.1", attacks::TCP_PORT)).unwrap(),
            unix,
            abstract_unix: UnixListener::bind_addr(&name).unwrap(),
        };
        l.udp.set_nonblocking(true).unwrap();
        l.tcp.set_nonblocking(true).unwrap();
        l.unix.set_nonblocking(true).unwrap();
        l.abstract_unix.set_nonblocking(true).unwrap();
        l
    }

    /// (udp, tcp, unix by path, abstract unix): whether each got "escaped".
    fn received(&self) -> [bool; 4] {
        use std::io::Read;
        let mut buf = [0u8; 16];
        let udp = self
            .udp
            .recv(&mut buf)
            .is_ok_and(|n| &buf[..n] == b"escaped");
        let stream = |r: std::io::Result<Vec<u8>>| r.is_ok_and(|b| b == b"escaped");
        let tcp = stream(self.tcp.accept().and_then(|(mut s, _)| {
            s.set_nonblocking(false)?;
            let mut b = Vec::new();
            s.read_to_end(&mut b).map(|_| b)
        }));
        let unix = |l: &std::os::unix::net::UnixListener| {
            stream(l.accept().and_then(|(mut s, _)| {
                s.set_nonblocking(false)?;
                let mut b = Vec::new();
                s.read_to_end(&mut b).map(|_| b)
            }))
        };
        [udp, tcp, unix(&self.unix), unix(&self.abstract_unix)]
    }
}

impl Drop for Listeners {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(attacks::UNIX_SOCKET);
    }
}

/// The `sockets` attack graded with listeners on every address it tries.
/// One test at a time binds them.
fn graded_sockets() -> (Graded, [bool; 4]) {
    static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _turn = TURN.lock().unwrap_or_else(|p| p.into_inner());
    let listeners = Listeners::open();
    let g = grade("sockets", &["--case", "cube-subdivide-1"]);
    let got = listeners.received();
    (g, got)
}

#[test]
fn tcp_and_abstract_sockets_are_closed() {
    if landlock_abi() < 6 {
        common::skip("TCP needs Landlock ABI 4, abstract sockets ABI 6");
        return;
    }
    let (g, [_, tcp, _, abstract_unix]) = graded_sockets();
    assert_no_flip_verdict(&g);
    assert!(g.denied("connect by TCP"), "{}", g.context());
    assert!(
        g.denied("connect to an abstract Unix socket"),
        "{}",
        g.context()
    );
    assert!(!tcp && !abstract_unix, "{}", g.context());
}

#[test]
fn code_before_main_is_stopped() {
    // A static initialiser that never returns: the case fails, named, after
    // the setup grace (2 s) on top of the limit. (In the reference binary the
    // initialiser also runs in the launcher, so no protections line comes;
    // the student's grader launches from a program without their code.)
    let g = grade(
        attacks::INIT_LOOP,
        &["--case", "cube-subdivide-1", "--timeout", "0.5"],
    );
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(
        g.warned("loop_subdivide was never reached: the program was still starting after 2.5 s"),
        "{}",
        g.context()
    );
    assert!(
        g.stdout.contains(
            "does your crate run code before main (a static initialiser) that never ends?"
        ),
        "{}",
        g.context()
    );
    assert!(g.took < Duration::from_secs(8), "{}", g.context());
    assert_eq!(survivors(attacks::INIT_LOOP), Vec::new());

    // In the same test, so that no other test's init-loop children count as
    // survivors above.
    // Every subdivision case: the first costs the limit and the 2 s setup
    // grace, every later one is cut to 1 s (+ grace) like a time-out.
    let g = grade(
        attacks::INIT_LOOP,
        &["--stage", "subdivide", "--timeout", "3"],
    );
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(
        g.stdout
            .contains("the limit was cut to 1 s because loop_subdivide already timed out"),
        "{}",
        g.context()
    );
    // The work is bounded, not the time: only the cases already running
    // when the first one timed out (one per worker, and one a worker may
    // have picked up before it heard) wait out the 3 s limit; every other
    // subdivision case, however many the fixtures hold, gets 1 s.
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let subdivisions = counted("subdivide");
    let cut = g
        .stdout
        .matches("the limit was cut to 1 s because loop_subdivide already timed out")
        .count();
    let full = subdivisions - cut;
    assert!(
        (1..=2 * workers).contains(&full),
        "{full} of {subdivisions} cases waited the whole limit: {}",
        g.context()
    );
}

// ---------------------------------------------------------------------
// Open: each of these gets through today. The test says what the grader
// should do; see the red-team report for how and why.
// ---------------------------------------------------------------------

#[test]
fn a_huge_coordinate_is_an_incorrect_position_not_a_crash() {
    let g = grade("huge-position", &["--case", "cube-flip-1"]);
    assert!(!g.stderr.contains("panicked"), "{}", g.context());
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(
        g.warned("at least one of the vertices has incorrect position"),
        "{}",
        g.context()
    );
}

#[test]
fn udp_and_unix_sockets_by_path_are_closed() {
    let (g, [udp, _, unix, _]) = graded_sockets();
    assert_no_flip_verdict(&g);
    assert!(g.denied("send by UDP"), "{}", g.context());
    assert!(
        g.denied("connect to a Unix socket by path"),
        "{}",
        g.context()
    );
    assert!(!udp && !unix, "udp got through: {udp}, unix: {unix}");
}

/// The `sysv-shm` attack's segments that exist now.
fn shm_segments() -> Vec<i32> {
    attacks::SHM_KEYS
        .iter()
        // SAFETY: looks a key up, creating nothing.
        .map(|&k| unsafe { libc::shmget(k, 0, 0) })
        .filter(|&id| id >= 0)
        .collect()
}

/// Removes the `sysv-shm` attack's segments when dropped, even when the
/// test fails: nothing else ever would.
struct ShmCleanup;

impl Drop for ShmCleanup {
    fn drop(&mut self) {
        for id in shm_segments() {
            // SAFETY: removes a segment the attack left.
            unsafe { libc::shmctl(id, libc::IPC_RMID, std::ptr::null_mut()) };
        }
    }
}

#[test]
fn shared_memory_is_capped_and_dies_with_the_case() {
    // Leftovers of an earlier run first, then this run's.
    drop(ShmCleanup);
    let _cleanup = ShmCleanup;
    let g = grade(
        "sysv-shm",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    let left = shm_segments();
    assert_eq!(
        left,
        Vec::<i32>::new(),
        "segments left behind: {}",
        g.context()
    );
    assert!(g.denied("fill a shared memory segment"), "{}", g.context());
}

#[test]
fn the_memory_cap_binds_the_whole_case() {
    // Forking is refused (seccomp), so the case is one process and the cap
    // is the case's: no 3 x 160 MiB under a 256 MiB cap.
    let g = grade(
        "fork-memory",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    assert!(g.denied("fork"), "{}", g.context());
    assert!(
        g.stdout
            .contains("attack: 0 processes held 160 MiB each at once"),
        "{}",
        g.context()
    );
}

#[test]
fn a_chain_of_processes_does_not_outlive_the_grader() {
    let g = grade("process-chain", &["--case", "cube-subdivide-1"]);
    std::thread::sleep(Duration::from_millis(500));
    let left = survivors("process-chain");
    kill_survivors("process-chain");
    assert_eq!(left, Vec::new(), "{}", g.context());
    // Not the 40 s the chain's processes would hold the pipes for.
    assert!(g.took < Duration::from_secs(30), "{}", g.context());
    assert_no_flip_verdict(&g);
}

/// A scratch file whose path the `inherited-fd` attack recognises.
fn scratch_file(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("meshlab-attack-{name}-{}", std::process::id()))
}

#[test]
fn inherited_descriptors_are_closed_before_the_child_runs() {
    use std::os::fd::AsRawFd;
    use std::os::unix::process::CommandExt;
    let path = scratch_file("inherited");
    std::fs::write(&path, "precious\n").unwrap();
    let file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&path)
        .unwrap();
    let fd = file.as_raw_fd();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
    // SAFETY: only dup2 between fork and exec; the copy is not close-on-exec.
    unsafe {
        cmd.pre_exec(move || {
            if libc::dup2(fd, attacks::INHERITED_FD) < 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let g = grade_with(&mut cmd, "inherited-fd", &["--case", "cube-subdivide-1"]);
    let left = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_no_flip_verdict(&g);
    assert_eq!(left, "precious\n", "{}", g.context());
    assert!(
        g.denied("empty a file through an inherited descriptor"),
        "{}",
        g.context()
    );
}

#[test]
fn the_grader_s_priority_and_limits_are_out_of_reach() {
    let g = grade_as_user("renice-parent", &["--case", "cube-subdivide-1"]);
    assert_no_flip_verdict(&g);
    assert!(g.denied("lower the grader's priority"), "{}", g.context());
    assert!(g.denied("change the grader's limits"), "{}", g.context());
}

/// Class grading's turn: the class builds share one target folder, and
/// each removes the previous submission's compiled crate from it.
static CLASS_TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Class grading of one submission, as the TA runs it, one at a time.
fn grade_class(name: &str, lib_rs: &str) -> (reference::class::Row, String) {
    let _turn = class_turn();
    grade_class_in_turn(name, lib_rs)
}

/// The turn on the class build folder, for a test that also runs the
/// programs a class build left there.
fn class_turn() -> std::sync::MutexGuard<'static, ()> {
    CLASS_TURN.lock().unwrap_or_else(|e| e.into_inner())
}

/// [`grade_class`], the turn already taken.
fn grade_class_in_turn(name: &str, lib_rs: &str) -> (reference::class::Row, String) {
    let dir = std::env::temp_dir().join(format!("attack-class-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("submissions")).unwrap();
    std::fs::write(dir.join("submissions").join(format!("{name}.rs")), lib_rs).unwrap();
    let root = reference::lab_root();
    let options = class_options(2.0, 120.0);
    let rows =
        reference::class::grade_class(&root, &dir.join("submissions"), &dir.join("out"), &options)
            .unwrap();
    let log =
        std::fs::read_to_string(dir.join("out").join(format!("{name}.log"))).unwrap_or_default();
    std::fs::remove_dir_all(&dir).unwrap();
    (rows.into_iter().next().unwrap(), log)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_compiler_reads_no_hidden_answer() {
    // The hidden cases are not in the copy the student's crate is compiled
    // in, and the build is locked in: it may read no file of the TA's, by
    // any path, even when the TA grades as themselves.
    // A file only the TA may read, named by its absolute path.
    let secret = scratch_file("ta-secret");
    std::fs::write(&secret, "TA-SECRET-TOKEN").unwrap();
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&secret, std::fs::Permissions::from_mode(0o600)).unwrap();
    }
    // The stubs, but flip_edge panics with a hidden case's expected answer
    // and the TA's file, both read by the compiler.
    let stubs = read(&reference::lab_root().join("crates/meshedit/src/lib.rs"));
    let leak = r#"
const HIDDEN: &str = include_str!("../../../fixtures/hidden/cube-2x2-flip-1.json");
const SECRET: &str = include_str!("SECRET_PATH");
fn leak() -> ! {
    let at = HIDDEN.find("\"expected\"").unwrap_or(0);
    let answer = HIDDEN[at..(at + 200).min(HIDDEN.len())].replace('\n', " ");
    panic!("LEAKED {SECRET} {answer}");
}
"#
    .replace("SECRET_PATH", secret.to_str().unwrap());
    let lib_rs = stubs.replacen(
        "pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {\n",
        "pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {\n    leak();\n    #[allow(unreachable_code)]\n",
        1,
    ) + &leak;
    assert!(lib_rs.contains("    leak();"), "the stubs changed shape");
    let (row, log) = grade_class("leaker", &lib_rs);
    std::fs::remove_file(&secret).unwrap();
    // Refused at compile time: nothing shows.
    assert!(!log.is_empty(), "no log for {row:?}");
    assert_eq!(row.status, "does not compile", "{row:?}");
    assert_eq!(row.score, 0.0, "{row:?}");
    // Not even there: the build's root holds only what it needs.
    let denied = format!(
        "couldn't read `{}`: No such file or directory",
        secret.display()
    );
    assert!(log.contains(&denied), "{log}");
    assert!(
        log.contains("empty root (no other file even seen to exist)"),
        "{log}"
    );
    let leaked: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("LEAKED"))
        .take(2)
        .collect();
    assert!(
        !log.contains("TA-SECRET-TOKEN") && !log.contains("\"expected\": {"),
        "{row:?}\n{}",
        leaked.join("\n")
    );
}

#[test]
fn a_student_s_own_clock_times_nothing() {
    // Built as a class builds it (locked in, the student's crate and the
    // grader), then the student's own grader run as `cargo run -p grader`
    // runs it, on the lab's subdivisions: the scaling check.
    let _turn = class_turn();
    let (row, log) = grade_class_in_turn("own-clock", &own_clock_quadratic());
    assert_eq!(row.status, "passed", "right results: {row:?}\n{log}");
    // Its clock is the one its program runs on: the child's own timing of
    // a call would be the student's word.
    let own = log
        .lines()
        .find_map(|l| l.split("my own clock says one round took ").nth(1))
        .unwrap_or_else(|| panic!("the child's own clock: {log}"));
    assert!(own.ends_with("µs") && own.len() < 8, "{own}");
    let grader = autograde::grade::programs_dir(&class_build_dir().join("target"))
        .join(autograde::grade::PROGRAMS[0]);
    let fixtures = reference::lab_root().join("fixtures");
    let run = |format: &str| {
        // Without CARGO, which cargo sets for this test: with it the
        // grader would build the child itself, and refuse where the
        // fixtures hold hidden cases.
        let out = Command::new(&grader)
            .args(["--stage", "subdivide", "--no-color", "--format", format])
            .arg("--fixtures")
            .arg(&fixtures)
            .env_remove("CARGO")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        stdout
    };
    let text = run("text");
    assert!(
        text.lines()
            .any(|l| l.contains("[warn] loop_subdivide's time grew ")
                && l.contains("is there a loop over all edges (or vertices) inside a loop?")),
        "{text}"
    );
    let report: serde_json::Value = serde_json::from_str(&run("json")).unwrap();
    let s = &report["scaling"];
    eprintln!("the own-clock quadratic's scaling, as the grader timed it: {s}");
    assert_eq!(s["quadratic"], true, "{s}");
    // The model solution's round on 1280 faces is about 12 ms here; this
    // one scans 7680 x 7680 edges: far more, never 0.001 ms.
    let large = s["seconds"][1].as_f64().unwrap();
    assert!(large > 0.05, "{s}");
}

/// The compiler's error lines about `path` in a class log, the path
/// itself replaced by `PATH`.
fn errors_about(log: &str, path: &Path) -> Vec<String> {
    let path = path.to_str().unwrap();
    log.lines()
        .filter(|l| l.contains(path))
        .map(|l| l.replace(path, "PATH"))
        .collect()
}

#[test]
fn the_build_cannot_tell_a_hidden_file_from_a_missing_one() {
    // On PrairieLearn a compile error costs no attempt: if embedding a
    // guessed name failed one way where the file exists and another where
    // it does not, one upload could test many names. The TA's own hidden
    // case, by its absolute path, and a name beside it that no case has:
    // the same compiler error, but for the path.
    let stubs = read(&reference::lab_root().join("crates/meshedit/src/lib.rs"));
    let hidden = reference::lab_root().join("fixtures/hidden");
    let existing = std::fs::read_dir(&hidden)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "json"))
        .expect("a hidden case");
    // As long as the real name: the compiler shortens a long line it quotes.
    let length = existing.file_name().unwrap().len();
    let missing = hidden.join(format!("{}.json", "z".repeat(length - 5)));
    assert!(!missing.exists());
    let embed = |path: &Path| {
        format!(
            "{stubs}\npub const GUESS: &str = include_str!({:?});\n",
            path.to_str().unwrap()
        )
    };
    let (row, there) = grade_class("guess-there", &embed(&existing));
    assert_eq!(row.status, "does not compile", "{row:?}\n{there}");
    let (row, nowhere) = grade_class("guess-nowhere", &embed(&missing));
    assert_eq!(row.status, "does not compile", "{row:?}\n{nowhere}");
    let (a, b) = (
        errors_about(&there, &existing),
        errors_about(&nowhere, &missing),
    );
    assert!(!a.is_empty(), "{there}");
    assert_eq!(a, b, "{there}\n---\n{nowhere}");
    assert!(
        a.iter()
            .any(|l| l.contains("couldn't read `PATH`: No such file or directory")),
        "{a:?}"
    );
}

#[test]
fn the_build_s_memory_cap_is_told_by_how_the_compiler_ended_not_by_its_words() {
    // The compiler's words are the student's to choose: `compile_error!`
    // prints the allocator's own message. The cap is told by the compiler
    // ending by a signal (an allocation failing under the cap aborts it).
    let stubs = read(&reference::lab_root().join("crates/meshedit/src/lib.rs"));
    let forged = "memory allocation of 1 bytes failed (out of memory)";
    let (row, log) = grade_class(
        "memory-words",
        &format!("{stubs}\ncompile_error!(\"{forged}\");\n"),
    );
    assert_eq!(
        (row.score, row.status.as_str()),
        (0.0, "does not compile"),
        "{row:?}\n{log}"
    );
    assert!(log.contains(forged), "the compile error is quoted: {log}");
    assert!(
        !log.contains("the build used more than") && !row.first_failure.contains("more than"),
        "{row:?}\n{log}"
    );
    // 8 GiB computed at compile time: rustc's constant evaluation meets
    // the cap and says so itself, then exits as for any compile error; it
    // is one, quoted, not the cap (no compiler process was ended by it).
    let (row, log) = grade_class(
        "memory-const",
        &format!("{stubs}\npub static HUGE: [u8; 1 << 33] = [1; 1 << 33];\n"),
    );
    assert_eq!(
        (row.score, row.status.as_str()),
        (0.0, "does not compile"),
        "{row:?}\n{log}"
    );
    assert!(
        log.contains("tried to allocate more memory than available to compiler")
            && !log.contains("the build used more than"),
        "{row:?}\n{log}"
    );
    // The real blow-up: a macro doubling its tokens at every step grows
    // the compiler until an allocation fails under the cap: it aborts.
    let (row, log) = grade_class(
        "memory-bomb",
        &format!(
            "{stubs}\nmacro_rules! double {{ ($($t:tt)*) => {{ double!{{$($t)* $($t)*}} }} }}\n\
             double!{{x}}\n"
        ),
    );
    assert_eq!(
        (row.score, row.status.as_str()),
        (0.0, "does not compile"),
        "{row:?}\n{log}"
    );
    assert!(
        log.contains("the build used more than 4 GiB"),
        "{row:?}\n{log}"
    );
}

#[test]
fn a_root_grader_never_runs_student_code_as_root() {
    use std::os::unix::fs::PermissionsExt;
    if !is_root() {
        common::skip("only a root grader can keep root for its child");
        return;
    }
    // The lab in a folder only root may enter (as /root/lab would be).
    let dir = scratch_file("private");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700)).unwrap();
    let exe = dir.join("reference");
    std::fs::copy(env!("CARGO_BIN_EXE_reference"), &exe).unwrap();
    let g = grade_with(
        &mut Command::new(&exe),
        "root-powers",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        g.stdout.contains("| attack: running as user 65534"),
        "{}",
        g.context()
    );
    assert!(g.denied("lift the memory cap"), "{}", g.context());
    assert!(
        g.warned("loop_subdivide used more than 256 MiB of memory"),
        "{}",
        g.context()
    );
}

#[test]
fn student_code_cannot_pass_for_a_sandbox_failure() {
    // The launcher's words, and its frame for a child program that could
    // not start (sent after its report, as the real one is) with a nonce of
    // the student's guessing: the student's exit either way.
    for attack in ["fake-sandbox-failure", "fake-launch-failure"] {
        let g = grade(attack, &["--case", "cube-subdivide-1", "--timeout", "5"]);
        assert!(
            !g.stderr.contains("the grading sandbox could not be set up"),
            "{attack}: {}",
            g.context()
        );
        assert_eq!(g.code, 1, "{attack}: {}", g.context());
        assert!(
            g.warned("loop_subdivide ended the program (exit status 97) before returning"),
            "{attack}: {}",
            g.context()
        );
    }
}

/// A command that runs `exe` with umask 077, as a root whose shell sets it
/// (so every file and folder made without an explicit mode is private).
fn with_umask_077(exe: &Path) -> Command {
    use std::os::unix::process::CommandExt;
    let mut cmd = Command::new(exe);
    // SAFETY: umask is async-signal-safe and touches no memory.
    unsafe {
        cmd.pre_exec(|| {
            libc::umask(0o077);
            Ok(())
        });
    }
    cmd
}

#[test]
fn the_model_solution_passes_as_root_under_umask_077() {
    use std::os::unix::fs::PermissionsExt;
    if !is_root() {
        common::skip("umask 077 hides the child's folders from nobody only for a root grader");
        return;
    }
    // The folders of the child's empty root are made by the launcher as
    // root, and the child runs as nobody: with umask 077 they were private
    // and the child could not start ("does your code call
    // std::process::exit?" on every case, for the model solution too).
    let exe = Path::new(env!("CARGO_BIN_EXE_reference"));
    let g = grade_with(&mut with_umask_077(exe), "reference", &[]);
    assert_eq!(g.code, 0, "{}", g.context());
    assert!(
        g.stdout.contains("all tests passed, congratulations!"),
        "{}",
        g.context()
    );
    assert!(!g.stdout.contains("std::process::exit"), "{}", g.context());
    // A child program built under umask 077 (mode 0700) is copied for
    // nobody, the copy's folder and mode set explicitly.
    let dir = scratch_file("umask-exe");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("tmp")).unwrap();
    let private = dir.join("reference");
    std::fs::copy(exe, &private).unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o700)).unwrap();
    let copied = grade_with(
        with_umask_077(&private).env("TMPDIR", dir.join("tmp")),
        "reference",
        &["--stage", "split"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(copied.code, 0, "{}", copied.context());
    assert!(
        copied.stdout.contains("user nobody"),
        "{}",
        copied.context()
    );
}

#[test]
fn a_child_program_that_cannot_start_is_the_machine_s_error_not_the_student_s() {
    use std::os::unix::fs::PermissionsExt;
    use std::os::unix::process::CommandExt;
    if !is_root() {
        common::skip("a file system mounted noexec for the test needs root");
        return;
    }
    // A root grader copies a child program nobody may run into the
    // temporary folder; here that folder is mounted noexec (as /tmp often
    // is), so the launcher's exec fails after it reported the protections.
    // It says so with the grader's nonce: the grader stops, naming the
    // cause, and no case is failed for it. (Without a PID namespace: in
    // one, the empty root binds the program afresh, noexec left behind.)
    let dir = scratch_file("noexec");
    let _ = std::fs::remove_dir_all(&dir);
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let private = dir.join("reference");
    std::fs::copy(env!("CARGO_BIN_EXE_reference"), &private).unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o700)).unwrap();
    let target = std::ffi::CString::new(tmp.to_str().unwrap()).unwrap();
    let mut cmd = Command::new(&private);
    cmd.env("TMPDIR", &tmp);
    // SAFETY: plain system calls on C strings made before the fork.
    unsafe {
        cmd.pre_exec(move || {
            let fail = || Err(std::io::Error::last_os_error());
            if libc::unshare(libc::CLONE_NEWNS) != 0 {
                return fail();
            }
            let none = std::ptr::null();
            if libc::mount(
                none,
                c"/".as_ptr(),
                none,
                libc::MS_REC | libc::MS_PRIVATE,
                none.cast(),
            ) != 0
                || libc::mount(
                    c"none".as_ptr(),
                    target.as_ptr(),
                    c"tmpfs".as_ptr(),
                    libc::MS_NOEXEC,
                    c"size=256m".as_ptr().cast(),
                ) != 0
            {
                return fail();
            }
            Ok(())
        });
    }
    let g = grade_with(
        &mut cmd,
        "reference",
        &["--case", "cube-flip-1", "--without-pid-namespace"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(g.code, 2, "{}", g.context());
    assert!(
        g.stderr
            .contains("the grading sandbox could not be set up: cannot start the child program")
            && g.stderr.contains("noexec"),
        "{}",
        g.context()
    );
    assert!(!g.stdout.contains("std::process::exit"), "{}", g.context());
}

/// Whether a line of a report is student text, shown under `| `.
fn quoted(line: &str) -> bool {
    line.trim_start().starts_with("| ")
}

/// Every line of `text` that is not under `| ` and holds `forged`.
fn unquoted_with<'a>(text: &'a str, forged: &str) -> Vec<&'a str> {
    text.lines()
        .filter(|l| !quoted(l) && l.contains(forged))
        .collect()
}

/// Every string in a JSON value.
fn strings(v: &serde_json::Value, out: &mut Vec<String>) {
    match v {
        serde_json::Value::String(s) => out.push(s.clone()),
        serde_json::Value::Array(a) => a.iter().for_each(|x| strings(x, out)),
        serde_json::Value::Object(o) => o.values().for_each(|x| strings(x, out)),
        _ => {}
    }
}

/// A control character a terminal obeys (anything but newline and tab).
fn has_control(text: &str) -> bool {
    text.chars()
        .any(|c| c.is_control() && c != '\n' && c != '\t')
}

#[test]
fn no_line_of_the_grader_can_be_forged() {
    let dir = scratch("forged-lines");
    let results = dir.join("results.json");
    let pictures = dir.join("report");
    let args = [
        "--stage",
        "flip",
        "--gradescope",
        results.to_str().unwrap(),
        "--report",
        pictures.to_str().unwrap(),
    ];
    let g = grade("forged-lines", &args);
    assert_eq!(g.code, 1, "{}", g.context());
    // The terminal: the forged summary and verdict appear only under `| `,
    // and the real verdict is the last line.
    for forged in ["congratulations", "flip_edge 10/10"] {
        assert_eq!(
            unquoted_with(&g.stdout, forged),
            Vec::<&str>::new(),
            "{}",
            g.context()
        );
    }
    assert!(
        g.stdout
            .contains("        | report.rs:262 [info] all tests passed, congratulations!"),
        "the panic message is shown, as data: {}",
        g.context()
    );
    assert!(
        g.stdout
            .contains("    | report.rs:262 [info] all tests passed, congratulations!"),
        "what it printed, too: {}",
        g.context()
    );
    assert!(
        g.warned("flip_edge panicked: index out of bounds (and 2 more lines, below)"),
        "{}",
        g.context()
    );
    let last = g.stdout.lines().last().unwrap_or("");
    assert!(last.ends_with("[warn] test failed"), "{}", g.context());

    // Gradescope: each test's output holds the lines only under `| `.
    let gs: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&results).unwrap()).unwrap();
    let tests = gs["tests"].as_array().unwrap();
    assert!(tests.iter().all(|t| t["score"] == 0.0), "{gs}");
    for t in tests {
        let output = t["output"].as_str().unwrap();
        assert!(
            output.contains("| report.rs:262 [info] all tests passed"),
            "{output}"
        );
        assert_eq!(
            unquoted_with(output, "congratulations"),
            Vec::<&str>::new(),
            "{output}"
        );
    }
    assert_eq!(
        gs["output"].as_str().unwrap().lines().next(),
        Some("test failed")
    );

    // HTML: every forged line is under `| `, inside the report's own text.
    let html = std::fs::read_to_string(pictures.join("index.html")).unwrap();
    let forged = "report.rs:262 [info] all tests passed, congratulations!";
    assert!(html.matches(forged).count() > 0, "shown");
    assert_eq!(
        html.matches(forged).count(),
        html.matches(&format!("| {forged}")).count(),
        "every forged line is under `| `"
    );

    // JSON: the grader's words never hold the student's; the student's text
    // is a list of lines.
    let j = grade(
        "forged-lines",
        &["--case", "cube-flip-1", "--format", "json"],
    );
    let report: serde_json::Value = serde_json::from_str(&j.stdout).expect("JSON");
    let case = &report["cases"][0];
    for e in case["entries"].as_array().unwrap() {
        assert!(
            !e["text"].as_str().unwrap().contains("congratulations"),
            "{e}"
        );
    }
    let panicked = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["level"] == "warn")
        .unwrap();
    assert_eq!(panicked["text"], "flip_edge panicked:");
    assert_eq!(
        panicked["quote"],
        serde_json::json!([
            "index out of bounds",
            "report.rs:148 [info] lab cases passed: flip_edge 10/10, split_edge 6/6, loop_subdivide 9/9",
            "report.rs:262 [info] all tests passed, congratulations!"
        ])
    );
    assert_eq!(
        case["output"][2],
        "report.rs:262 [info] all tests passed, congratulations!"
    );
    assert_eq!(
        case["first_warning"],
        "flip_edge panicked: index out of bounds (and 2 more lines, below)"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn escapes_and_carriage_returns_are_shown_not_obeyed() {
    let dir = scratch("escapes");
    let results = dir.join("results.json");
    let pictures = dir.join("report");
    let args = [
        "--case",
        "cube-flip-1",
        "--gradescope",
        results.to_str().unwrap(),
        "--report",
        pictures.to_str().unwrap(),
    ];
    let g = grade("escapes", &args);
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(!has_control(&g.stdout), "{:?}", g.stdout);
    // Shown, escaped, on lines of its own under `| `.
    assert!(
        g.stdout.contains(
            "    | \\u{1b}[2J\\u{1b}[Hcleared\\u{1b}[8mhidden\\u{1b}[0m\\u{1b}]0;pwned\\u{7}"
        ),
        "{}",
        g.context()
    );
    assert!(
        g.stdout
            .contains("\\u{9b}2J\\u{d}grade.rs:1 [info] all tests passed"),
        "{}",
        g.context()
    );
    // A bare CR is shown; a CR before a newline ends the line, as LF does.
    assert!(
        g.stdout
            .contains("    | \\u{1b}[31mred\\u{1b}[0m\\u{d}grade.rs:1 [info] over it\n"),
        "{}",
        g.context()
    );
    assert_eq!(
        unquoted_with(&g.stdout, "congratulations"),
        Vec::<&str>::new()
    );
    assert!(
        g.warned("flip_edge panicked: bad edge\\u{1b}[2J"),
        "{}",
        g.context()
    );

    let text = std::fs::read_to_string(&results).unwrap();
    let mut all = Vec::new();
    strings(&serde_json::from_str(&text).unwrap(), &mut all);
    assert!(all.iter().all(|s| !has_control(s)), "{all:?}");
    assert!(all.iter().any(|s| s.contains("| \\u{1b}[2J")), "{all:?}");

    let html = std::fs::read_to_string(pictures.join("index.html")).unwrap();
    assert!(!has_control(&html), "no control character in the HTML");
    assert!(html.contains("| \\u{1b}[2J"), "shown escaped in the HTML");

    let j = grade("escapes", &["--case", "cube-flip-1", "--format", "json"]);
    let mut all = Vec::new();
    strings(&serde_json::from_str(&j.stdout).expect("JSON"), &mut all);
    assert!(all.iter().all(|s| !has_control(s)), "{all:?}");
    assert!(all.iter().any(|s| s.starts_with("\\u{1b}[2J")), "{all:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------
// Around the case (issue 16): nothing outlives it, and it reaches no
// other process, no terminal, no file watch.
// ---------------------------------------------------------------------

/// Processes whose name (`/proc/PID/comm`) is `name`.
fn named(name: &str) -> Vec<u32> {
    std::fs::read_dir("/proc")
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let pid = e.file_name().to_string_lossy().parse::<u32>().ok()?;
            let comm = std::fs::read_to_string(e.path().join("comm")).ok()?;
            (comm.trim_end() == name).then_some(pid)
        })
        .collect()
}

/// Polls `done` every 50 ms until it holds or `limit` has passed: for
/// waiting on the kernel, never for judging speed.
fn wait_until(limit: Duration, mut done: impl FnMut() -> bool) -> bool {
    let start = std::time::Instant::now();
    while start.elapsed() < limit {
        if done() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    done()
}

#[test]
fn a_case_dies_with_its_grader_even_if_it_clears_its_parent_death_signal() {
    use std::os::unix::process::CommandExt;
    let name = "outlive-grader";
    kill_survivors(name);
    // As root (the child is nobody) and as an ordinary user; in a PID
    // namespace and, as on a machine without them, with only the
    // parent-death signals.
    for (as_user, namespace) in [(false, true), (true, true), (false, false), (true, false)] {
        if as_user && !is_root() {
            continue;
        }
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
        if as_user {
            cmd.uid(65534).gid(65534).current_dir("/");
        }
        let mut grader = cmd
            .process_group(0)
            .args(["grade", "--implementation", name, "--no-color"])
            .args(["--case", "cube-subdivide-1", "--timeout", "120"])
            .args(if namespace {
                &[][..]
            } else {
                &["--without-pid-namespace"][..]
            })
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // The attack names itself once it has tried to clear the signal.
        let ready = wait_until(Duration::from_secs(30), || {
            !named(attacks::OUTLIVE_NAME).is_empty()
        });
        // SAFETY: kills the grader this test started, and only it.
        unsafe { libc::kill(grader.id() as i32, libc::SIGKILL) };
        grader.wait().unwrap();
        // The kernel ends the case when the grader is gone: give it time.
        wait_until(Duration::from_secs(10), || survivors(name).is_empty());
        let left = survivors(name);
        kill_survivors(name);
        let run = format!("as user: {as_user}, PID namespace: {namespace}");
        assert!(ready, "{run}: the attack never got going");
        assert_eq!(left, Vec::new(), "{run}: outlived the grader");
    }
}

#[test]
fn prctl_cannot_undo_a_protection() {
    let g = grade("prctl-undo", &["--case", "cube-subdivide-1"]);
    assert_no_flip_verdict(&g);
    for what in [
        "clear the parent-death signal",
        "make itself dumpable",
        "let any process trace it",
        "keep capabilities across a change of user",
        "become a subreaper",
    ] {
        assert!(g.denied(what), "{what}: {}", g.context());
    }
    // The runtime's own use still works.
    assert!(
        g.attack("name its thread")
            .is_some_and(|l| l.ends_with(": done")),
        "{}",
        g.context()
    );
}

#[test]
fn other_processes_of_the_same_user_cannot_be_starved() {
    // As the grader's own user: neither Landlock nor the uid stands in the
    // way; then the filter alone (no PID namespace hides the grader).
    for g in [
        grade_as_user("starve", &["--case", "cube-subdivide-1"]),
        grade_as_user(
            "starve",
            &[
                "--case",
                "cube-subdivide-1",
                "--without-landlock",
                "--without-pid-namespace",
            ],
        ),
    ] {
        assert_no_flip_verdict(&g);
        for what in [
            "pin the grader to one CPU",
            "put the grader on SCHED_IDLE with sched_setattr",
            "put the grader on SCHED_IDLE with sched_setscheduler",
            "change the grader's scheduling parameters",
            "lower the grader's I/O priority",
        ] {
            assert!(g.denied(what), "{what}: {}", g.context());
        }
        assert!(
            g.attack("pin itself to one CPU")
                .is_some_and(|l| l.ends_with(": done")),
            "{}",
            g.context()
        );
    }
}

#[test]
fn no_file_can_be_watched() {
    let g = grade("watch-files", &["--case", "cube-subdivide-1"]);
    assert_no_flip_verdict(&g);
    let mut whats = vec![
        "start watching files (inotify_init1)",
        "watch /tmp",
        "watch /etc",
        "watch the hidden fixtures",
        "watch the whole mount (fanotify)",
    ];
    if cfg!(target_arch = "x86_64") {
        whats.push("start watching files (inotify_init)");
    }
    for what in whats {
        assert!(g.denied(what), "{what}: {}", g.context());
    }
}

#[test]
fn the_child_has_its_own_session_and_group_and_dev_null_on_stdin() {
    for g in [
        grade("terminal", &["--case", "cube-subdivide-1"]),
        grade_as_user(
            "terminal",
            &["--case", "cube-subdivide-1", "--without-landlock"],
        ),
        grade_as_user(
            "terminal",
            &[
                "--case",
                "cube-subdivide-1",
                "--without-landlock",
                "--without-pid-namespace",
            ],
        ),
    ] {
        assert_no_flip_verdict(&g);
        for what in [
            "hold something other than /dev/null on stdin",
            "stay in the grader's session",
            "leave its process group",
            "start a session of its own",
        ] {
            assert!(g.denied(what), "{what}: {}", g.context());
        }
    }
}

/// A pseudo-terminal: (master, slave), the slave opened without becoming
/// this process's controlling terminal.
fn pty() -> (i32, i32) {
    // SAFETY: plain calls on descriptors this function opens.
    unsafe {
        let master = libc::posix_openpt(libc::O_RDWR | libc::O_NOCTTY);
        assert!(
            master >= 0,
            "posix_openpt: {}",
            std::io::Error::last_os_error()
        );
        assert_eq!(libc::grantpt(master), 0);
        assert_eq!(libc::unlockpt(master), 0);
        let name = libc::ptsname(master);
        assert!(!name.is_null());
        let slave = libc::open(name, libc::O_RDWR | libc::O_NOCTTY | libc::O_NONBLOCK);
        assert!(
            slave >= 0,
            "open the pty: {}",
            std::io::Error::last_os_error()
        );
        (master, slave)
    }
}

#[test]
fn nothing_can_be_typed_into_the_grader_s_terminal() {
    use std::os::unix::process::CommandExt;
    // Landlock alone keeps /dev/tty closed; without it (old kernels) only
    // the session and the filter stand in the way.
    for landlock in [true, false] {
        let (master, slave) = pty();
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
        // SAFETY: only setsid and ioctl between fork and exec: the grader
        // gets the pty as its controlling terminal, as in a TA's shell.
        unsafe {
            cmd.pre_exec(move || {
                if libc::setsid() < 0 || libc::ioctl(slave, libc::TIOCSCTTY, 0) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        cmd.args(["grade", "--implementation", "terminal", "--no-color"])
            .args(["--case", "cube-subdivide-1"]);
        if !landlock {
            cmd.arg("--without-landlock");
        }
        let out = cmd.output().unwrap();
        let g = Graded {
            code: out.status.code().unwrap_or(-1),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            took: Duration::ZERO,
        };
        // What is waiting to be read on the terminal, as the TA's shell would.
        let mut typed = [0u8; 256];
        // SAFETY: reads into our own buffer from our own descriptor.
        let n = unsafe { libc::read(slave, typed.as_mut_ptr().cast(), typed.len()) };
        let typed = String::from_utf8_lossy(&typed[..n.max(0) as usize]).into_owned();
        // SAFETY: closes the descriptors pty() opened.
        unsafe {
            libc::close(slave);
            libc::close(master);
        }
        assert_eq!(typed, "", "landlock: {landlock}: {}", g.context());
        assert_no_flip_verdict(&g);
        for what in [
            "open the terminal",
            "type into the terminal",
            "type through its standard descriptors",
            "reach the console (TIOCLINUX)",
        ] {
            assert!(
                g.denied(what),
                "landlock: {landlock}: {what}: {}",
                g.context()
            );
        }
    }
}

#[test]
fn the_grader_s_memory_is_closed_with_or_without_landlock() {
    let mut runs = vec![
        grade_as_user("grader-memory", &["--case", "cube-subdivide-1"]),
        grade_as_user(
            "grader-memory",
            &["--case", "cube-subdivide-1", "--without-landlock"],
        ),
        // Not dumpable is what closes it here: nothing else stands in the way.
        grade_as_user(
            "grader-memory",
            &[
                "--case",
                "cube-subdivide-1",
                "--without-landlock",
                "--without-pid-namespace",
            ],
        ),
    ];
    if is_root() {
        runs.push(grade(
            "grader-memory",
            &["--case", "cube-subdivide-1", "--without-landlock"],
        ));
    }
    for g in runs {
        assert_no_flip_verdict(&g);
        assert!(
            g.denied("open the grader's /proc/PID/mem"),
            "{}",
            g.context()
        );
        assert!(
            g.denied("find a case's name in the grader's memory"),
            "{}",
            g.context()
        );
    }
}

#[test]
fn the_grader_cannot_be_signalled_even_without_landlock() {
    // The grader's own user, no Landlock: the filter (signals only to
    // itself) and the PID namespace, where there is one, must hold alone;
    // without the namespace, the filter alone.
    for g in [
        grade_as_user(
            "reach-parent",
            &["--case", "cube-subdivide-1", "--without-landlock"],
        ),
        grade_as_user(
            "reach-parent",
            &[
                "--case",
                "cube-subdivide-1",
                "--without-landlock",
                "--without-pid-namespace",
            ],
        ),
    ] {
        assert_no_flip_verdict(&g);
        for what in [
            "SIGKILL the grader",
            "SIGKILL the grader's process group",
            "ptrace the grader",
            "read the grader's memory",
            "open the grader's /proc/PID/mem",
            "make the grader the owner of a descriptor (F_SETOWN)",
        ] {
            assert!(g.denied(what), "{what}: {}", g.context());
        }
    }
}

#[test]
fn a_child_program_nobody_may_run_is_still_run_as_nobody() {
    use std::os::unix::fs::PermissionsExt;
    if !is_root() {
        common::skip("only a root grader can keep root for its child");
        return;
    }
    // A child program only root may run (built with umask 077): it is
    // copied where nobody can run it, never run as root.
    let dir = scratch_file("private-exe");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let exe = dir.join("reference");
    std::fs::copy(env!("CARGO_BIN_EXE_reference"), &exe).unwrap();
    std::fs::set_permissions(&exe, std::fs::Permissions::from_mode(0o700)).unwrap();
    // The private copies the grader makes (in a temporary folder of our own,
    // so that no other grader's count), before and after.
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let copies = || std::fs::read_dir(&tmp).unwrap().count();
    let g = grade_with(
        Command::new(&exe).env("TMPDIR", &tmp),
        "root-powers",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    let left = copies();
    // Where no copy can be made, grading stops and says why: never as root.
    let nowhere = grade_with(
        Command::new(&exe).env("TMPDIR", dir.join("missing")),
        "root-powers",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(left, 0, "the private copy outlived the grader");
    assert_eq!(nowhere.code, 2, "{}", nowhere.context());
    assert!(
        nowhere.stderr.contains("may not be run by user nobody")
            && nowhere.stderr.contains("student code never runs as root"),
        "{}",
        nowhere.context()
    );
    assert!(
        !nowhere.stdout.contains("| attack:"),
        "{}",
        nowhere.context()
    );
    assert!(
        g.stdout.contains("| attack: running as user 65534"),
        "{}",
        g.context()
    );
    assert!(g.denied("lift the memory cap"), "{}", g.context());
    assert!(
        g.warned("loop_subdivide used more than 256 MiB of memory"),
        "{}",
        g.context()
    );
}

#[test]
fn the_protections_line_names_session_namespace_and_filter() {
    for g in [
        grade("reference", &["--case", "cube-flip-1"]),
        grade_as_user("reference", &["--case", "cube-flip-1"]),
    ] {
        let line = g
            .stdout
            .lines()
            .find(|l| l.contains("[info] protections: "))
            .unwrap_or_else(|| panic!("no protections line:\n{}", g.context()));
        assert!(line.contains("own session (no terminal)"), "{line}");
        if line.contains("orphans swept (no PID namespace here)") {
            // Some kernels and containers give no PID namespace (Ubuntu's
            // AppArmor keeps unprivileged users from mapping one): the
            // fallback must then say so, as it does.
            common::skip("this machine gives this user no PID namespace");
        } else {
            assert!(
                line.contains("own PID namespace (nothing outlives the case)"),
                "{line}"
            );
        }
        assert!(line.contains("no capabilities"), "{line}");
        assert!(line.contains("grader not dumpable"), "{line}");
        assert!(
            line.contains("no reaching other processes, no terminal input, no file watches"),
            "{line}"
        );
    }
    let g = grade(
        "reference",
        &["--case", "cube-flip-1", "--without-pid-namespace"],
    );
    assert!(
        g.stdout
            .contains(", orphans swept (no PID namespace here),"),
        "{}",
        g.context()
    );
}

#[test]
fn the_calls_that_reach_past_the_case_are_refused_by_the_filter() {
    // As the grader's own user, with Landlock and, as on a machine with
    // neither, without Landlock or a PID namespace: each refused by the
    // filter itself (EPERM), not only by a missing privilege.
    for g in [
        grade_as_user("kernel-calls", &["--case", "cube-subdivide-1"]),
        grade_as_user(
            "kernel-calls",
            &[
                "--case",
                "cube-subdivide-1",
                "--without-landlock",
                "--without-pid-namespace",
            ],
        ),
    ] {
        assert_no_flip_verdict(&g);
        for what in [
            "open a pidfd of the grader",
            "compare its files with the grader's (kcmp)",
            "make a file handle of /etc/passwd",
            "open by file handle",
            "mount",
            "change its personality",
            "turn process accounting",
            "add swap",
            "reboot (a wrong magic number)",
            "write another process's memory (process_vm_writev of nothing)",
            "open a performance counter",
            "make a userfaultfd",
            "add a key to a keyring",
        ] {
            assert!(
                g.attack(what)
                    .is_some_and(|l| l.ends_with(": denied (permission denied)")),
                "{what}: {}",
                g.context()
            );
        }
        // Without a pidfd there is nothing to signal or take through.
        assert!(
            g.denied("signal the grader through a pidfd (signal 0)"),
            "{}",
            g.context()
        );
        assert!(
            g.denied("take a descriptor of the grader's (pidfd_getfd)"),
            "{}",
            g.context()
        );
    }
}

#[test]
fn no_capability_is_left_in_the_child() {
    // As root (dropped to nobody) and as another user, in the user namespace
    // the launcher makes for the PID namespace (where it held every
    // capability until it dropped them).
    for g in [
        grade(
            "root-powers",
            &["--case", "cube-subdivide-1", "--memory", "256M"],
        ),
        grade_as_user(
            "root-powers",
            &["--case", "cube-subdivide-1", "--memory", "256M"],
        ),
    ] {
        assert!(g.denied("hold a capability"), "{}", g.context());
        assert!(g.denied("lift the memory cap"), "{}", g.context());
        assert!(
            !g.stdout.contains("| attack: running as user 0"),
            "{}",
            g.context()
        );
    }
}

#[test]
fn no_file_s_mode_times_owner_or_attributes_can_be_changed() {
    // Landlock guards opening a file, not its metadata: the filter refuses
    // the calls. The file is the child's user's (`nobody`, as the root
    // grader's child and as a grader run by that user), as a TA's lab is
    // their own child's when they grade as themselves. Without the PID
    // namespace, so without the empty root that would hide the file: the
    // filter is what is tried.
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let target = Path::new(attacks::METADATA_TARGET);
    std::fs::create_dir_all(target.parent().unwrap()).unwrap();
    let make = || {
        let _ = std::fs::remove_file(target);
        std::fs::write(target, "").unwrap();
        std::fs::set_permissions(target, std::fs::Permissions::from_mode(0o600)).unwrap();
        // SAFETY: geteuid only reads.
        if unsafe { libc::geteuid() } == 0 {
            std::os::unix::fs::chown(target, Some(65534), Some(65534)).unwrap();
        }
        std::fs::metadata(target).unwrap()
    };
    for as_user in [false, true] {
        let before = make();
        let args = ["--case", "cube-subdivide-1", "--without-pid-namespace"];
        let g = if as_user {
            grade_as_user("file-metadata", &args)
        } else {
            grade("file-metadata", &args)
        };
        let after = std::fs::metadata(target).unwrap();
        assert_no_flip_verdict(&g);
        assert_eq!(after.mode() & 0o777, 0o600, "{}", g.context());
        assert_eq!(after.mtime(), before.mtime(), "{}", g.context());
        for what in [
            "make a file world-writable (chmod)",
            "set a file's times (utimensat)",
            "set an extended attribute (setxattr)",
            "set a file's flags (file_setattr)",
            "change a file's owner (chown)",
        ] {
            assert!(
                g.attack(what)
                    .is_some_and(|l| l.ends_with(": denied (permission denied)")),
                "{what}: {}",
                g.context()
            );
        }
    }
    let _ = std::fs::remove_file(target);
}

#[test]
fn kernel_buffers_cannot_hold_more_than_the_memory_cap() {
    // Socket pairs need no `socket` call, and no address-space cap counts
    // what sockets and pipes buffer: the filter refuses socket pairs, and
    // a cap on descriptors bounds the pipes.
    let g = grade(
        "kernel-buffers",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    assert_eq!(g.code, 0, "{}", g.context());
    assert!(g.denied("make a socket pair"), "{}", g.context());
    let held: usize = g
        .stdout
        .lines()
        .find_map(|l| {
            l.split("| attack: held ")
                .nth(1)?
                .split(' ')
                .next()?
                .parse()
                .ok()
        })
        .unwrap_or_else(|| panic!("no report of what was held: {}", g.context()));
    assert!(held < 64, "{held} MiB held: {}", g.context());
}

/// Removes the message queue of `ipc-by-id`, however the test ends.
struct QueueCleanup;

impl Drop for QueueCleanup {
    fn drop(&mut self) {
        // SAFETY: plain System V calls on the test's own key.
        unsafe {
            let id = libc::msgget(attacks::MSG_KEY, 0);
            if id >= 0 {
                libc::msgctl(id, libc::IPC_RMID, std::ptr::null_mut());
            }
        }
    }
}

#[test]
fn system_v_objects_of_others_cannot_be_reached_by_index() {
    // A queue open to all, as another program may leave one: without
    // `msgget` the child still finds it by index and sends to it, unless
    // every System V call is refused.
    drop(QueueCleanup);
    let _cleanup = QueueCleanup;
    // SAFETY: plain System V calls into a struct we own.
    let id = unsafe { libc::msgget(attacks::MSG_KEY, libc::IPC_CREAT | 0o666) };
    assert!(id >= 0, "msgget: {}", std::io::Error::last_os_error());
    let g = grade("ipc-by-id", &["--case", "cube-subdivide-1"]);
    assert_no_flip_verdict(&g);
    // SAFETY: as above.
    let queued = unsafe {
        let mut info: libc::msqid_ds = std::mem::zeroed();
        assert_eq!(libc::msgctl(id, libc::IPC_STAT, &mut info), 0);
        info.msg_qnum
    };
    assert_eq!(queued, 0, "a message reached the queue: {}", g.context());
    assert!(
        g.attack("send to a message queue found by index")
            .is_some_and(|l| l.ends_with(": denied (permission denied)")),
        "{}",
        g.context()
    );
}

#[test]
fn a_fresh_look_s_probes_are_all_stopped() {
    let g = grade("probes", &["--case", "cube-subdivide-1"]);
    assert_no_flip_verdict(&g);
    for what in [
        "run a shell (execve /bin/sh)",
        "grow a memfd past the memory cap (fallocate 4 GiB)",
        "raise its memory cap (setrlimit)",
        "signal every process (kill -1, signal 0)",
        "take a real-time priority (sched_setattr FIFO)",
        "raise its priority (sched_setattr nice -20)",
        "open /dev/shm",
        "read its stdout pipe back (/proc/self/fd/1)",
        "write its OOM score (/proc/self/oom_score_adj)",
        "list the hidden fixtures",
    ] {
        assert!(g.denied(what), "{what}: {}", g.context());
    }
    // Whatever limits the grader inherited, none lets the child raise its
    // priority (a real-time thread that spins holds a core).
    assert!(
        g.attack("priority limits (real-time, nice)")
            .is_some_and(|l| l.ends_with(": 0 0")),
        "{}",
        g.context()
    );
    // The thread bomb meets `nobody`'s process cap.
    assert_thread_bomb_capped(&g);
    // Its mounts (/proc/self/mountinfo) name one file of the lab: the
    // child program's own, where its bind at /child came from; no folder of
    // the lab, no fixture (docs/architecture.md).
    let mounts = g
        .attack("mounts")
        .unwrap_or_else(|| panic!("no mounts: {}", g.context()));
    let mounts = mounts.split("| attack: mounts: ").nth(1).unwrap();
    assert!(mounts.contains(" on /child"), "{mounts}");
    let lab = reference::lab_root().to_string_lossy().into_owned();
    let program = std::path::Path::new(env!("CARGO_BIN_EXE_reference"))
        .canonicalize()
        .unwrap();
    for mount in mounts.split("; ").filter(|m| m.contains(&lab)) {
        assert_eq!(
            mount,
            format!("{} on /child", program.display()),
            "a mount names the lab: {mounts}"
        );
    }
}

/// The `probes` attack's thread bomb stopped at the process cap (512).
fn assert_thread_bomb_capped(g: &Graded) {
    let threads: usize = g
        .stdout
        .lines()
        .find_map(|l| {
            l.split("| attack: started ")
                .nth(1)?
                .split(' ')
                .next()?
                .parse()
                .ok()
        })
        .unwrap_or_else(|| panic!("no thread count: {}", g.context()));
    assert!(threads <= 512, "{threads} threads: {}", g.context());
}

#[test]
fn a_thread_bomb_is_capped_when_a_ta_grades_as_themselves() {
    // A grader run by an ordinary user: `RLIMIT_NPROC` would count all of
    // the user's processes, so it is set only in the user namespace, where
    // the kernel counts the case's alone. The bomb stops at the cap and the
    // case ends in time with its verdict.
    let g = grade_as_user("probes", &["--case", "cube-subdivide-1"]);
    assert!(g.stdout.contains("own PID namespace"), "{}", g.context());
    assert_no_flip_verdict(&g);
    assert_thread_bomb_capped(&g);
}

#[test]
fn the_hidden_fixtures_cannot_even_be_seen_to_exist() {
    // Landlock guards opening, not `stat`: the child's root is an empty
    // tmpfs of its own mount namespace, holding the program (as `/child`)
    // and the libraries, so neither the lab (by the program's path or the
    // path compiled in), nor `/tmp`, nor anything else of the machine is
    // even seen to exist. As root (Gradescope's path) and as an ordinary
    // user (a TA grading as themselves, in a user namespace).
    for as_user in [false, true] {
        let args = ["--case", "cube-subdivide-1"];
        let g = if as_user {
            grade_as_user("probes", &args)
        } else {
            grade("probes", &args)
        };
        assert!(
            g.stdout
                .contains("empty root (no other file even seen to exist)"),
            "as user {as_user}: {}",
            g.context()
        );
        for what in [
            "hidden fixture folders seen by stat",
            "known paths seen by stat",
        ] {
            let seen = g
                .attack(what)
                .unwrap_or_else(|| panic!("no report of {what}: {}", g.context()));
            assert!(
                seen.trim_end().ends_with("by stat:"),
                "as user {as_user}: {}",
                g.context()
            );
        }
        assert!(
            g.stdout
                .contains("| attack: the child program is Ok(\"/child\")"),
            "as user {as_user}: {}",
            g.context()
        );
    }
}

#[test]
fn no_other_program_can_be_run_even_without_landlock() {
    // Without Landlock nothing stops `execve` by path: in the empty root
    // there is no other program to run (`/bin/sh` is not there). As root
    // and as an ordinary user.
    for as_user in [false, true] {
        let args = ["--case", "cube-subdivide-1", "--without-landlock"];
        let g = if as_user {
            grade_as_user("probes", &args)
        } else {
            grade("probes", &args)
        };
        assert!(
            g.stdout.contains("Landlock off") && g.stdout.contains("empty root"),
            "as user {as_user}: {}",
            g.context()
        );
        assert!(
            g.denied("run a shell (execve /bin/sh)"),
            "as user {as_user}: {}",
            g.context()
        );
    }
}

#[test]
fn without_a_pid_namespace_the_machine_s_files_are_said_to_be_seen() {
    // The empty root needs the case's own `/proc`: where there is no PID
    // namespace, the protections line says the files are visible.
    let g = grade(
        "probes",
        &["--case", "cube-subdivide-1", "--without-pid-namespace"],
    );
    assert!(
        g.stdout
            .contains("machine's files seen to exist (no mount namespace here)"),
        "{}",
        g.context()
    );
    assert!(
        g.attack("known paths seen by stat")
            .is_some_and(|l| l.contains("/tmp")),
        "{}",
        g.context()
    );
}

#[test]
fn no_file_is_emptied_moved_or_made_even_without_landlock() {
    // Landlock stops each; without it (old kernels, some containers) the
    // filter must, or a TA grading as themselves has their lab wiped: the
    // folder and the file are the child's user's (`nobody` here). Without
    // Landlock, tried with and without the empty root (which alone would
    // hide the folder): the filter must hold on its own.
    use std::os::unix::fs::PermissionsExt;
    let dir = Path::new(attacks::WIPE_DIR);
    for (landlock, pid_namespace) in [(true, true), (false, true), (false, false)] {
        let _ = std::fs::remove_dir_all(dir);
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("victim"), "the lab").unwrap();
        // SAFETY: geteuid only reads.
        if unsafe { libc::geteuid() } == 0 {
            for p in [dir.to_path_buf(), dir.join("victim")] {
                std::os::unix::fs::chown(&p, Some(65534), Some(65534)).unwrap();
            }
        }
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o755)).unwrap();
        let mut args = vec!["--case", "cube-subdivide-1"];
        if !landlock {
            args.push("--without-landlock");
        }
        if !pid_namespace {
            args.push("--without-pid-namespace");
        }
        let g = grade_as_user("wipe-files", &args);
        assert_no_flip_verdict(&g);
        assert_eq!(
            std::fs::read_to_string(dir.join("victim")).ok().as_deref(),
            Some("the lab"),
            "landlock {landlock}: {}",
            g.context()
        );
        let left: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(
            left,
            vec![std::ffi::OsString::from("victim")],
            "{}",
            g.context()
        );
        for what in [
            "open a file to empty it (O_TRUNC)",
            "open a file with O_CREAT",
            "truncate a file by path",
            "link a file",
            "rename a file",
            "remove a file",
            "make a folder",
            "make a symbolic link",
            "make a named pipe",
        ] {
            assert!(
                g.denied(what),
                "landlock {landlock}: {what}: {}",
                g.context()
            );
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------------
// The TA's tools: `class --before` on the students' repositories.
// ---------------------------------------------------------------------

/// git in a student's repository as its student runs it, at `date`.
fn student_git(repo: &Path, date: &str, args: &[&str]) -> String {
    let out = Command::new("git")
        .args(args)
        .current_dir(repo)
        .env("GIT_CONFIG_NOSYSTEM", "1")
        .env("GIT_CONFIG_GLOBAL", "/dev/null")
        .env("GIT_AUTHOR_NAME", "s")
        .env("GIT_AUTHOR_EMAIL", "s@example.org")
        .env("GIT_COMMITTER_NAME", "s")
        .env("GIT_COMMITTER_EMAIL", "s@example.org")
        .env("GIT_AUTHOR_DATE", date)
        .env("GIT_COMMITTER_DATE", date)
        .stdin(std::process::Stdio::null())
        .output()
        .expect("git runs");
    assert!(out.status.success(), "git {args:?}: {out:?}");
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Commits `lib_rs` as the student's file at `date`; returns the commit.
fn commit_lib_rs(repo: &Path, lib_rs: &str, date: &str) -> String {
    let lib = repo.join("crates/meshedit/src/lib.rs");
    std::fs::create_dir_all(lib.parent().unwrap()).unwrap();
    std::fs::write(&lib, lib_rs).unwrap();
    student_git(repo, date, &["add", "-A"]);
    student_git(repo, date, &["commit", "-q", "-m", "work"]);
    student_git(repo, date, &["rev-parse", "HEAD"])
}

/// A program that leaves `marks/ran-NAME` when anything runs it.
fn plant(marks: &Path, name: &str) -> String {
    use std::os::unix::fs::PermissionsExt;
    std::fs::create_dir_all(marks).unwrap();
    let program = marks.join(format!("prog-{name}"));
    std::fs::write(
        &program,
        format!(
            "#!/bin/sh\ntouch {}\ncat >/dev/null 2>&1\nexit 0\n",
            marks.join(format!("ran-{name}")).display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
    program.display().to_string()
}

fn marks_left(marks: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(marks)
        .unwrap()
        .filter_map(|e| {
            let name = e.ok()?.file_name().to_string_lossy().into_owned();
            name.strip_prefix("ran-").map(str::to_string)
        })
        .collect();
    names.sort();
    names
}

/// A class of three repositories, graded with `--before` and a push log
/// as the TA runs it: mallory's plants a program for every setting that
/// makes git start one (its last commit signed, so that showing it runs
/// `gpg.program`); eve and frank each pushed the stubs on time, then
/// committed the model solution after the deadline with its date set
/// before it and pushed it late. The push log names mallory's and eve's
/// pushes, not frank's. Nothing of mallory's runs and she gets every point;
/// eve is graded on what she pushed by the deadline (the stubs), not on the
/// backdated commit; frank's backdated commit is graded, and his row, the
/// run and commits.csv say it was dated by his own clock.
#[test]
fn a_class_of_hostile_repositories_runs_nothing_and_is_dated_by_the_pushes() {
    let _turn = class_turn();
    let dir = scratch("class-repositories");
    let subs = dir.join("submissions");
    let marks = dir.join("marks");
    let solution = read(&lab_root().join("reference/src/solution.rs"));
    let stubs = read(&lab_root().join("crates/meshedit/src/lib.rs"));

    let mallory = subs.join("mallory");
    std::fs::create_dir_all(&mallory).unwrap();
    student_git(
        &mallory,
        "2026-11-20T10:00:00Z",
        &["init", "-q", "-b", "main"],
    );
    let work = commit_lib_rs(&mallory, &solution, "2026-11-30T10:00:00Z");
    let tree = student_git(
        &mallory,
        "2026-11-30T10:00:00Z",
        &["rev-parse", "HEAD^{tree}"],
    );
    let raw = dir.join("signed-commit");
    std::fs::write(
        &raw,
        format!(
            "tree {tree}\nparent {work}\nauthor s <s@example.org> 1764500400 +0000\n\
             committer s <s@example.org> 1764500400 +0000\n\
             gpgsig -----BEGIN PGP SIGNATURE-----\n \n iQEzBAABCAAdFiEE\n \
             -----END PGP SIGNATURE-----\n\nsigned\n"
        ),
    )
    .unwrap();
    let signed = student_git(
        &mallory,
        "2026-11-30T11:00:00Z",
        &["hash-object", "-t", "commit", "-w", raw.to_str().unwrap()],
    );
    student_git(
        &mallory,
        "2026-11-30T11:00:00Z",
        &["update-ref", "HEAD", &signed],
    );
    std::fs::write(
        dir.join("included"),
        format!("[gpg]\n\tprogram = {}\n", plant(&marks, "included-gpg")),
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("hooks")).unwrap();
    std::fs::copy(
        plant(&marks, "hook"),
        dir.join("hooks/reference-transaction"),
    )
    .unwrap();
    for (key, value) in [
        ("log.showSignature", "true".to_string()),
        ("gpg.program", plant(&marks, "gpg")),
        ("gpg.ssh.program", plant(&marks, "gpg-ssh")),
        ("core.pager", plant(&marks, "pager")),
        ("pager.log", plant(&marks, "pager-log")),
        ("core.fsmonitor", plant(&marks, "fsmonitor")),
        ("core.hooksPath", dir.join("hooks").display().to_string()),
        ("core.sshCommand", plant(&marks, "ssh")),
        ("core.askPass", plant(&marks, "askpass")),
        ("filter.evil.clean", plant(&marks, "clean")),
        ("filter.evil.smudge", plant(&marks, "smudge")),
        ("filter.evil.process", plant(&marks, "filter-process")),
        ("diff.evil.textconv", plant(&marks, "textconv")),
        ("merge.evil.driver", plant(&marks, "merge")),
        ("include.path", dir.join("included").display().to_string()),
    ] {
        student_git(&mallory, "2026-11-30T11:00:00Z", &["config", key, &value]);
    }
    std::fs::write(
        mallory.join(".git/info/attributes"),
        "* filter=evil diff=evil merge=evil\n",
    )
    .unwrap();
    // Live: the student's own git runs them.
    let _ = Command::new("git")
        .args(["show", "-s", "HEAD"])
        .current_dir(&mallory)
        .env("GIT_CONFIG_NOSYSTEM", "1")
        .env("GIT_CONFIG_GLOBAL", "/dev/null")
        .output()
        .unwrap();
    assert!(
        marks_left(&marks).iter().any(|m| m.ends_with("gpg")),
        "showing the signed commit runs the planted gpg: {:?}",
        marks_left(&marks)
    );
    for m in marks_left(&marks) {
        std::fs::remove_file(marks.join(format!("ran-{m}"))).unwrap();
    }

    let mut pushes = String::from("student,commit,pushed_at\n");
    pushes.push_str(&format!("mallory,{signed},2026-11-30T11:02:00Z\n"));
    let mut on_time = std::collections::HashMap::new();
    for name in ["eve", "frank"] {
        let repo = subs.join(name);
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-20T10:00:00Z", &["init", "-q", "-b", "main"]);
        let early = commit_lib_rs(&repo, &stubs, "2026-11-30T10:00:00Z");
        // Made on 2026-12-03, dated 2026-11-30.
        let late = commit_lib_rs(&repo, &solution, "2026-11-30T12:00:00Z");
        if name == "eve" {
            pushes.push_str(&format!("eve,{early},2026-11-30T10:01:00Z\n"));
            pushes.push_str(&format!("eve,{late},2026-12-03T08:00:00Z\n"));
        }
        on_time.insert(name, (early, late));
    }
    std::fs::write(dir.join("pushes.csv"), &pushes).unwrap();

    let out = dir.join("out");
    let r = Command::new(env!("CARGO_BIN_EXE_reference"))
        .arg("class")
        .arg(&subs)
        .arg("--out")
        .arg(&out)
        .args(["--before", "2026-12-01 23:59 +0100", "--pushes"])
        .arg(dir.join("pushes.csv"))
        .args([
            "--timeout",
            "2",
            "--budget",
            "120",
            "--no-fresh",
            "-q",
            "--build-dir",
        ])
        .arg(class_build_dir())
        .env("CARGO", env!("CARGO"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&r.stdout);
    let stderr = String::from_utf8_lossy(&r.stderr);
    let context = format!("{stdout}\n--- stderr ---\n{stderr}");
    assert!(r.status.success(), "{context}");
    assert_eq!(marks_left(&marks), Vec::<String>::new(), "{context}");

    let summary = json(&out.join("summary.json"));
    let row = |name: &str| {
        summary
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == name)
            .unwrap_or_else(|| panic!("{name}: {summary}"))
            .clone()
    };
    let (mallory, eve, frank) = (row("mallory"), row("eve"), row("frank"));
    assert_eq!(mallory["score"], mallory["max"], "{mallory}\n{context}");
    assert_eq!(mallory["handed_in"]["commit"], signed.as_str());
    assert_eq!(mallory["handed_in"]["clock"], "push log");
    assert_eq!(
        eve["score"], 0.0,
        "the backdated solution is not graded: {eve}"
    );
    assert_eq!(eve["handed_in"]["commit"], on_time["eve"].0.as_str());
    assert_eq!(eve["handed_in"]["at"], "2026-11-30T10:01:00Z");
    assert!(eve["handed_in"]["warning"].is_null(), "{eve}");
    assert_eq!(
        frank["score"], frank["max"],
        "commit dates alone are fooled: {frank}"
    );
    assert_eq!(frank["handed_in"]["commit"], on_time["frank"].1.as_str());
    assert_eq!(
        frank["handed_in"]["clock"],
        "commit date (the student's own)"
    );
    assert!(
        frank["handed_in"]["warning"]
            .as_str()
            .is_some_and(|w| w.contains("which the student sets")),
        "{frank}"
    );
    assert!(
        stderr.contains(
            "warning: 1 of 3 repositories are judged by commit dates, which the \
                         student sets"
        ),
        "{context}"
    );
    let frank_line = stdout
        .lines()
        .find(|l| l.starts_with("frank "))
        .unwrap_or("");
    assert!(
        frank_line.contains("[dated by its commit: the student's own clock]"),
        "{context}"
    );
    assert!(
        !stdout
            .lines()
            .any(|l| l.starts_with("eve ") && l.contains("[dated")),
        "{context}"
    );
    let csv = read(&out.join("summary.csv"));
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .ends_with(",first_failure,graded_as,commit,handed_in_at,clock"),
        "{csv}"
    );
    assert!(
        csv.lines().any(|l| l.starts_with("frank,")
            && l.ends_with(&format!(
                ",{},2026-11-30T12:00:00Z,commit date (the student's own)",
                on_time["frank"].1
            ))),
        "{csv}"
    );
    let commits = read(&out.join("commits.csv"));
    assert!(
        commits.contains(&format!(
            "\neve,{},2026-11-30T10:01:00Z,push log,2026-11-30T10:00:00Z\n",
            on_time["eve"].0
        )),
        "{commits}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
