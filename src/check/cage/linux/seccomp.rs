//! A seccomp filter for the renderer: the kernel's keyrings closed. No namespace separates
//! them, so two lines run as the same user (every line, as user `nobody` under root) could
//! pass pictures through the user keyring; `add_key`, `request_key` and `keyctl` fail with
//! EPERM. Everything else the namespaces, the root of its own and Landlock already hold.
//!
//! A classic BPF program, checked by architecture first: a 64-bit x86 program may call the
//! 32-bit system calls (`int 0x80`) and the x32 ones, whose numbers differ; each is filtered
//! by its own numbers, and a call of an architecture the filter does not know is refused.

// prctl(PR_SET_SECCOMP) and the probe's add_key have no safe wrapper in rustix.
#![allow(unsafe_code)]

use libc::{BPF_ABS, BPF_JEQ, BPF_JGE, BPF_JMP, BPF_K, BPF_LD, BPF_RET, BPF_W, sock_filter};

/// `struct seccomp_data`: the system call's number, then its architecture.
const NUMBER_AT: u32 = 0;
const ARCHITECTURE_AT: u32 = 4;

/// The architectures a process here may call the kernel as, each with its keyring calls
/// (`add_key`, `request_key`, `keyctl`) and, where it has one, the bit of the x32 calls.
#[cfg(target_arch = "x86_64")]
const ARCHITECTURES: &[(u32, [u32; 3], Option<u32>)] = &[
    // AUDIT_ARCH_X86_64; x32 calls are the same architecture with bit 30 set.
    (0xC000_003E, [248, 249, 250], Some(0x4000_0000)),
    // AUDIT_ARCH_I386.
    (0x4000_0003, [286, 287, 288], None),
];
#[cfg(target_arch = "aarch64")]
const ARCHITECTURES: &[(u32, [u32; 3], Option<u32>)] = &[
    // AUDIT_ARCH_AARCH64; 32-bit ARM programs run as AUDIT_ARCH_ARM.
    (0xC000_00B7, [217, 218, 219], None),
    (0x4000_0028, [309, 310, 311], None),
];
#[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
const ARCHITECTURES: &[(u32, [u32; 3], Option<u32>)] = &[];

/// One instruction before its jumps are known: to the refusal at the program's end, or past
/// the block of another architecture.
enum Step {
    Load(u32),
    Return(u32),
    RefuseIfEqual(u32),
    RefuseIfAtLeast(u32),
    SkipUnlessEqual(u32, u8),
}

/// What a refused call returns: EPERM.
fn refused() -> u32 {
    libc::SECCOMP_RET_ERRNO | (libc::EPERM as u32 & libc::SECCOMP_RET_DATA)
}

/// The filter's program: made before the renderer's process forks, bound after ([`bind`]).
pub fn program() -> Vec<sock_filter> {
    let mut steps = Vec::new();
    for &(architecture, calls, x32) in ARCHITECTURES {
        let block = 2 + usize::from(x32.is_some()) + calls.len() + 1;
        steps.push(Step::Load(ARCHITECTURE_AT));
        // Past this architecture's block (its loads, tests and return) when it is another.
        steps.push(Step::SkipUnlessEqual(architecture, (block - 2) as u8));
        steps.push(Step::Load(NUMBER_AT));
        if let Some(bit) = x32 {
            steps.push(Step::RefuseIfAtLeast(bit));
        }
        steps.extend(calls.map(Step::RefuseIfEqual));
        steps.push(Step::Return(libc::SECCOMP_RET_ALLOW));
    }
    // An architecture the filter does not know: refused rather than let through unfiltered.
    steps.push(Step::Return(refused()));
    let refusal = steps.len() - 1;
    let code = |parts: u32| parts as u16;
    steps
        .iter()
        .enumerate()
        .map(|(at, step)| {
            let to_refusal = (refusal - at - 1) as u8;
            match *step {
                Step::Load(offset) => sock_filter {
                    code: code(BPF_LD | BPF_W | BPF_ABS),
                    jt: 0,
                    jf: 0,
                    k: offset,
                },
                Step::Return(value) => sock_filter {
                    code: code(BPF_RET | BPF_K),
                    jt: 0,
                    jf: 0,
                    k: value,
                },
                Step::RefuseIfEqual(k) => sock_filter {
                    code: code(BPF_JMP | BPF_JEQ | BPF_K),
                    jt: to_refusal,
                    jf: 0,
                    k,
                },
                Step::RefuseIfAtLeast(k) => sock_filter {
                    code: code(BPF_JMP | BPF_JGE | BPF_K),
                    jt: to_refusal,
                    jf: 0,
                    k,
                },
                Step::SkipUnlessEqual(k, skip) => sock_filter {
                    code: code(BPF_JMP | BPF_JEQ | BPF_K),
                    jt: 0,
                    jf: skip,
                    k,
                },
            }
        })
        .collect()
}

/// Binds the calling thread, and all it starts, by `filter` ([`program`]); needs
/// no_new_privs set first (the renderer's child sets it). `Err` where the kernel has no
/// seccomp or the system's architecture is not one the filter knows. Allocates nothing: it
/// runs between fork and exec.
pub fn bind(filter: &[sock_filter]) -> std::io::Result<()> {
    if ARCHITECTURES.is_empty() {
        return Err(std::io::Error::from(std::io::ErrorKind::Unsupported));
    }
    let program = libc::sock_fprog {
        len: filter.len() as u16,
        filter: filter.as_ptr().cast_mut(),
    };
    // SAFETY: `program` points at `filter`, alive for the call; the kernel copies it.
    let done = unsafe {
        libc::prctl(
            libc::PR_SET_SECCOMP,
            libc::SECCOMP_MODE_FILTER as libc::c_ulong,
            &raw const program as libc::c_ulong,
        )
    };
    if done == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// Whether the filter holds here, for the report: tried once a run, on a thread that ends at
/// once (a filter binds the thread that sets it), in check's own process.
pub fn keyrings_state() -> Result<(), String> {
    static STATE: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    STATE.get_or_init(probe).clone()
}

fn probe() -> Result<(), String> {
    let tried = std::thread::Builder::new().spawn(|| {
        rustix::thread::set_no_new_privs(true).map_err(std::io::Error::from)?;
        bind(&program())?;
        // The filter refuses what it should: a key cannot be made.
        // SAFETY: the strings are NUL-terminated and live for the call; the payload is empty.
        let made = unsafe {
            libc::syscall(
                libc::SYS_add_key,
                c"user".as_ptr(),
                c"raycast-probe".as_ptr(),
                c"".as_ptr(),
                0usize,
                libc::KEY_SPEC_THREAD_KEYRING,
            )
        };
        let error = std::io::Error::last_os_error();
        if made == -1 && error.raw_os_error() == Some(libc::EPERM) {
            Ok(())
        } else {
            Err(std::io::Error::other("a key could still be made"))
        }
    });
    match tried.map(|thread| thread.join()) {
        Ok(Ok(Ok(()))) => Ok(()),
        Ok(Ok(Err(e))) => Err(format!("no seccomp filter: {e}")),
        _ => Err("not tried (no thread could be started)".to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_jump_lands_inside_the_program() {
        let program = program();
        for (at, step) in program.iter().enumerate() {
            if step.code & 0x07 == BPF_JMP as u16 {
                for jump in [step.jt, step.jf] {
                    assert!(at + 1 + usize::from(jump) < program.len(), "{at}");
                }
            }
        }
        assert_eq!(
            program.last().map(|s| s.k),
            Some(refused()),
            "the program ends refusing"
        );
    }

    #[test]
    fn a_thread_bound_by_the_filter_cannot_make_a_key() {
        if ARCHITECTURES.is_empty() {
            return;
        }
        assert_eq!(keyrings_state(), Ok(()));
    }
}
