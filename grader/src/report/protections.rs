//! The protections line: what the case's launcher put in force
//! ([`Protections`], facts it reported), said in the lab's words at the
//! top of every report.

use crate::isolate::protections::Protections;
use crate::text::format_bytes;

/// The line for the protections the first case reported (`None`: no
/// case reported them), `not_dumpable` when the grader made itself
/// non-dumpable.
pub fn line(launched: Option<&Protections>, not_dumpable: bool) -> String {
    let Some(p) = launched else {
        return "protections: unknown (no case reported them)".into();
    };
    let landlock = match p.landlock {
        0 => "Landlock off (the kernel has none: student code can read files)".to_string(),
        abi => format!("Landlock ABI {abi} (no files, no network, no signals out)"),
    };
    let memory = format!("memory cap {}", format_bytes(p.memory));
    let session = if p.own_session {
        ", own session (no terminal)"
    } else {
        ""
    };
    let pids = if p.pid_namespace {
        ", own PID namespace (nothing outlives the case)"
    } else {
        ", orphans swept (no PID namespace here)"
    };
    let root = if p.empty_root {
        ", empty root (no other file even seen to exist)"
    } else {
        ", machine's files seen to exist (no mount namespace here)"
    };
    let user = if p.nobody { ", user nobody" } else { "" };
    let caps = if p.no_capabilities {
        ", no capabilities"
    } else {
        ""
    };
    let filter = if p.seccomp {
        ", seccomp (no new processes, no sockets, no IPC, no reaching other processes, \
         no terminal input, no file watches)"
    } else {
        ", no seccomp filter"
    };
    let grader = if not_dumpable {
        ", grader not dumpable"
    } else {
        ""
    };
    format!(
        "protections: {landlock}, {memory}, own process group{session}{pids}{root}{user}{caps}\
         {filter}{grader}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_names_each_protection() {
        let all = Protections {
            landlock: 6,
            memory: 2 << 30,
            nobody: true,
            own_session: true,
            pid_namespace: true,
            empty_root: true,
            no_capabilities: true,
            seccomp: true,
            pid: 1,
        };
        assert_eq!(
            line(Some(&all), true),
            "protections: Landlock ABI 6 (no files, no network, no signals out), \
             memory cap 2 GiB, own process group, own session (no terminal), \
             own PID namespace (nothing outlives the case), \
             empty root (no other file even seen to exist), user nobody, no capabilities, \
             seccomp (no new processes, no sockets, no IPC, no reaching other processes, \
             no terminal input, no file watches), grader not dumpable"
        );
        let off = line(
            Some(&Protections {
                memory: 1 << 30,
                ..Default::default()
            }),
            false,
        );
        assert!(off.contains("Landlock off"), "{off}");
        assert!(
            off.contains("orphans swept (no PID namespace here)"),
            "{off}"
        );
        assert!(!off.contains("nobody"), "{off}");
        assert!(
            off.contains("machine's files seen to exist (no mount namespace here)"),
            "{off}"
        );
        assert!(line(None, true).contains("unknown"));
    }
}
