//! Attacks on the grader by a student who has read its source, each an
//! entry of the catalogue (`reference/src/hostile.rs`) run through the real
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

use reference::hostile;

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
        let _ = std::fs::remove_file(hostile::UNIX_SOCKET);
        let unix = UnixListener::bind(hostile::UNIX_SOCKET).unwrap();
        // Open to the child whatever user it runs as.
        std::fs::set_permissions(hostile::UNIX_SOCKET, std::fs::Permissions::from_mode(0o777))
            .unwrap();
        let name = SocketAddr::from_abstract_name(hostile::ABSTRACT_SOCKET).unwrap();
        let l = Listeners {
            udp: std::net::UdpSocket::bind(("127.0.0.1", hostile::UDP_PORT)).unwrap(),
            tcp: std::net::TcpListener::bind(("127.0.0.1", hostile::TCP_PORT)).unwrap(),
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
        let _ = std::fs::remove_file(hostile::UNIX_SOCKET);
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
        hostile::INIT_LOOP,
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
    assert_eq!(survivors(hostile::INIT_LOOP), Vec::new());

    // In the same test, so that no other test's init-loop children count as
    // survivors above.
    // Every subdivision case: the first costs the limit and the 2 s setup
    // grace, every later one is cut to 1 s (+ grace) like a time-out.
    let g = grade(
        hostile::INIT_LOOP,
        &["--stage", "subdivide", "--timeout", "3"],
    );
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(
        g.stdout
            .contains("the limit was cut to 1 s because loop_subdivide already timed out"),
        "{}",
        g.context()
    );
    // 17 cases on 2 workers: well under 17 x (3 + 2) s.
    assert!(g.took < Duration::from_secs(40), "{}", g.context());
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
    hostile::SHM_KEYS
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
    assert!(g.took < Duration::from_secs(12), "{}", g.context());
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
            if libc::dup2(fd, hostile::INHERITED_FD) < 0 {
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

/// Class grading of one submission, as the TA runs it.
fn grade_class(name: &str, lib_rs: &str) -> (reference::class::Row, String) {
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
    let denied = format!("couldn't read `{}`: Permission denied", secret.display());
    assert!(log.contains(&denied), "{log}");
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
    let g = grade(
        "fake-sandbox-failure",
        &["--case", "cube-subdivide-1", "--timeout", "5"],
    );
    assert!(
        !g.stderr.contains("the grading sandbox could not be set up"),
        "{}",
        g.context()
    );
    assert_eq!(g.code, 1, "{}", g.context());
    assert!(
        g.warned("loop_subdivide ended the program (exit status 97) before returning"),
        "{}",
        g.context()
    );
}
