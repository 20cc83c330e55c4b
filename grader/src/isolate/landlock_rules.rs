//! Landlock for a case's child: every file and network access handled,
//! only the child program, the shared libraries and its own `/proc/self`
//! allowed. On kernels (or systems) without Landlock it is off and the
//! protections line says so; the other protections stand alone.

use std::path::Path;

/// Landlock is Linux's: elsewhere the other protections stand alone.
#[cfg(not(target_os = "linux"))]
pub fn landlock(_: &std::fs::File) -> Result<i32, String> {
    Ok(0)
}

/// A Landlock ruleset that handles every file and network access and
/// scopes signals and abstract sockets (best effort up to ABI 6): nothing
/// is allowed until a launcher adds its rules. Shared by the case's and
/// the build's launchers.
#[cfg(target_os = "linux")]
pub fn denying_everything() -> Result<landlock::RulesetCreated, String> {
    use landlock::{
        Access, AccessFs, AccessNet, CompatLevel, Compatible, Ruleset, RulesetAttr, Scope, ABI,
    };
    let abi = ABI::V6;
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    Ruleset::default()
        .set_compatibility(CompatLevel::BestEffort)
        .handle_access(AccessFs::from_all(abi))
        .map_err(|e| fail(&e))?
        .handle_access(AccessNet::from_all(abi))
        .map_err(|e| fail(&e))?
        .scope(Scope::from_all(abi))
        .map_err(|e| fail(&e))?
        .create()
        .map_err(|e| fail(&e))
}

/// Applies Landlock; returns the ABI in force (0 when the kernel has none).
#[cfg(target_os = "linux")]
pub fn landlock(program: &std::fs::File) -> Result<i32, String> {
    use landlock::{
        AccessFs, LandlockStatus, PathBeneath, PathFd, RulesetCreatedAttr, RulesetStatus,
    };
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    let mut ruleset = denying_everything()?;
    // The program by its open descriptor: its folder may be closed to
    // `nobody`, which this process may be by now.
    ruleset = ruleset
        .add_rule(PathBeneath::new(
            program,
            AccessFs::ReadFile | AccessFs::Execute,
        ))
        .map_err(|e| fail(&e))?;
    // Its own /proc entries (the pid survives exec): the runtime reads
    // /proc/self/maps to find the main thread's stack guard, without which
    // a stack overflow is a bare SIGSEGV instead of a named one.
    if let Ok(fd) = PathFd::new("/proc/self") {
        ruleset = ruleset
            .add_rule(PathBeneath::new(fd, AccessFs::ReadFile))
            .map_err(|e| fail(&e))?;
    }
    // The dynamic loader and the shared libraries the child program needs.
    for dir in [
        "/lib",
        "/lib64",
        "/usr/lib",
        "/usr/lib64",
        "/etc/ld.so.cache",
    ] {
        if let Ok(fd) = PathFd::new(dir) {
            let rights = if Path::new(dir).is_dir() {
                AccessFs::ReadFile | AccessFs::Execute
            } else {
                AccessFs::ReadFile.into()
            };
            ruleset = ruleset
                .add_rule(PathBeneath::new(fd, rights))
                .map_err(|e| fail(&e))?;
        }
    }
    let status = ruleset.restrict_self().map_err(|e| fail(&e))?;
    Ok(match (status.ruleset, status.landlock) {
        (RulesetStatus::NotEnforced, _) => 0,
        (_, LandlockStatus::Available { effective_abi, .. }) => effective_abi as i32,
        _ => 0,
    })
}
