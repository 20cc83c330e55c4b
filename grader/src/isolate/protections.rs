//! What a case's launcher put in force, as facts: the launcher sends them
//! as its first frame ([`crate::isolate::wire::Frame::Sandbox`]) before any
//! student code runs, the runner reads the ones it acts on (a PID
//! namespace decides whether orphans are swept; the child's pid is the
//! process whose CPU clock it reads), and `report/protections.rs` says
//! them in the protections line. Nothing parses words.

use serde::Serialize;

/// The protections of one case's child.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Protections {
    /// Landlock's ABI, 0 where it is off.
    pub landlock: u8,
    /// The memory cap (`RLIMIT_AS`), bytes.
    pub memory: u64,
    /// The child runs as `nobody` (a root launcher dropped to it).
    pub nobody: bool,
    /// The launcher leads a session of its own (no terminal).
    pub own_session: bool,
    /// The case has a PID namespace of its own (nothing outlives it).
    pub pid_namespace: bool,
    /// The child's root is an empty, read-only tmpfs (no other file seen).
    pub empty_root: bool,
    /// Every capability is dropped.
    pub no_capabilities: bool,
    /// The seccomp filter is applied.
    pub seccomp: bool,
    /// The child program's process id as the grader sees it, read by the
    /// launcher before the program ran.
    pub pid: u32,
}

/// The bits of [`Protections`]' flags on the wire, in order.
const FLAGS: usize = 6;

impl Protections {
    fn flags(&self) -> [bool; FLAGS] {
        [
            self.nobody,
            self.own_session,
            self.pid_namespace,
            self.empty_root,
            self.no_capabilities,
            self.seccomp,
        ]
    }

    /// The wire's bytes: the ABI, the cap, the flags as bits, the pid.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = vec![self.landlock];
        out.extend_from_slice(&self.memory.to_le_bytes());
        let bits = self
            .flags()
            .iter()
            .enumerate()
            .fold(0u8, |b, (i, &on)| b | (u8::from(on) << i));
        out.push(bits);
        out.extend_from_slice(&self.pid.to_le_bytes());
        out
    }

    /// The length of [`Protections::to_bytes`].
    pub const LEN: usize = 1 + 8 + 1 + 4;

    /// Back from [`Protections::to_bytes`]; `None` for any other bytes.
    pub fn from_bytes(bytes: &[u8]) -> Option<Protections> {
        if bytes.len() != Self::LEN || bytes[9] >> FLAGS != 0 {
            return None;
        }
        let bit = |i: usize| bytes[9] & (1 << i) != 0;
        Some(Protections {
            landlock: bytes[0],
            memory: u64::from_le_bytes(bytes[1..9].try_into().ok()?),
            nobody: bit(0),
            own_session: bit(1),
            pid_namespace: bit(2),
            empty_root: bit(3),
            no_capabilities: bit(4),
            seccomp: bit(5),
            pid: u32::from_le_bytes(bytes[10..14].try_into().ok()?),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn protections_cross_the_wire_whole() {
        let p = Protections {
            landlock: 6,
            memory: 2 << 30,
            nobody: true,
            own_session: true,
            pid_namespace: false,
            empty_root: true,
            no_capabilities: true,
            seccomp: false,
            pid: 4242,
        };
        let bytes = p.to_bytes();
        assert_eq!(bytes.len(), Protections::LEN);
        assert_eq!(Protections::from_bytes(&bytes), Some(p));
        let mut odd = bytes.clone();
        odd[9] |= 1 << 7;
        assert_eq!(Protections::from_bytes(&odd), None);
        assert_eq!(Protections::from_bytes(&bytes[1..]), None);
    }
}
