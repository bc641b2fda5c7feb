//! A renderer's own root: in a mount namespace of the line's init, a new root on a tmpfs of the
//! line's size (`--disk`), holding the system's folders (read-only), the renderer's own program
//! and `--allow-read` paths (read-only), a fresh /proc, a few devices, a private /tmp and
//! /dev/shm, and its work and output folders at the paths the line names; nothing else. No
//! suite, no other student, no socket of the machine's is there to be found. Whatever the
//! renderer writes, however many files, however deep or locked, is in that tmpfs, bounded by
//! its size and count, and gone the moment the line's last process is; only the pictures it
//! was asked for are copied out.

use std::fs;
use std::io;
use std::os::fd::{AsFd, OwnedFd};
use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
use std::path::{Path, PathBuf};

use rustix::fs::{Mode, OFlags};
use rustix::mount::{MountFlags, MountPropagationFlags, UnmountFlags};

use super::{Request, confine};

/// The devices a program may expect; each bound from the machine's /dev.
/// No tty: the renderer has no terminal of its own (its init is a session of its own), and
/// the teacher's is never its to write to.
const DEVICES: &[&str] = &["null", "zero", "full", "random", "urandom"];

/// The line's root, once the init has moved into it: what it needs to give the pictures back.
pub struct Root {
    /// The real output folder, opened before the old root went away.
    outputs: OwnedFd,
}

/// Builds the renderer's root for `request` and makes it the init's (and so the renderer's)
/// root. `fresh_proc`: the init is the first process of a PID namespace, so /proc can show it
/// alone. Runs in the init, in a mount namespace of its own, before the renderer starts; an
/// `Err` leaves the old root in place (the report says the renderer saw the machine's files).
pub fn enter(request: &Request, fresh_proc: bool) -> Result<Root, String> {
    let failed = |what: &str, path: &Path, e: io::Error| format!("{what} {}: {e}", path.display());
    // Nothing mounted here reaches the machine's namespace.
    rustix::mount::mount_change(
        "/",
        MountPropagationFlags::REC | MountPropagationFlags::PRIVATE,
    )
    .map_err(|e| format!("making the mounts private: {e}"))?;
    let root = request
        .root
        .as_deref()
        .ok_or("check gave it no folder to mount it on")?;
    let size = std::ffi::CString::new(format!(
        "size={},nr_inodes={},mode=755",
        request.limits.disk, request.limits.files
    ))
    .map_err(|e| e.to_string())?;
    rustix::mount::mount(
        "raycast-line",
        root,
        "tmpfs",
        MountFlags::NOSUID | MountFlags::NODEV,
        size.as_c_str(),
    )
    .map_err(|e| failed("mounting a tmpfs on", root, e.into()))?;
    let inside = |path: &Path| root.join(path.strip_prefix("/").unwrap_or(path));
    for folder in confine::SYSTEM {
        let path = Path::new(folder);
        match fs::symlink_metadata(path) {
            // /bin -> usr/bin where /usr is merged: the same link in the new root.
            Ok(m) if m.file_type().is_symlink() => {
                let target = fs::read_link(path).map_err(|e| failed("reading", path, e))?;
                std::os::unix::fs::symlink(target, inside(path))
                    .map_err(|e| failed("linking", path, e))?;
            }
            Ok(m) if m.is_dir() && !matches!(*folder, "/proc" | "/dev") => {
                bind_read_only(path, &inside(path))?;
            }
            _ => {}
        }
    }
    make_devices(&inside(Path::new("/dev")))?;
    let proc = inside(Path::new("/proc"));
    fs::create_dir(&proc).map_err(|e| failed("making", &proc, e))?;
    if fresh_proc {
        rustix::mount::mount(
            "proc",
            &proc,
            "proc",
            MountFlags::NOSUID | MountFlags::NODEV | MountFlags::NOEXEC,
            None,
        )
        .map_err(|e| failed("mounting proc on", &proc, e.into()))?;
    } else {
        rustix::mount::mount_bind_recursive("/proc", &proc)
            .map_err(|e| failed("binding /proc on", &proc, e.into()))?;
    }
    for temporary in confine::PRIVATE_TEMPORARY {
        open_folder(&inside(Path::new(temporary)), 0o1777)?;
    }
    // Outer folders first; what lies in one bound already, or in a system folder, is there.
    let mut readable: Vec<&Path> = request.readable.iter().map(PathBuf::as_path).collect();
    readable.sort_by_key(|path| path.components().count());
    let mut bound: Vec<&Path> = Vec::new();
    for path in readable {
        let there = |outer: &&Path| path.starts_with(outer);
        // /proc and /dev are made anew, not bound: a path in them (a submission copied to
        // /dev/shm) is bound as any other.
        let bound_whole = |s: &&&str| !matches!(**s, "/proc" | "/dev");
        if confine::SYSTEM
            .iter()
            .filter(bound_whole)
            .map(Path::new)
            .any(|s| there(&s))
            || bound.iter().any(there)
        {
            continue;
        }
        bind_read_only(path, &inside(path))?;
        bound.push(path);
    }
    // The suite (and anything else check keeps from renderers) stays hidden even where a
    // readable path holds it: an empty folder over it.
    for hidden in &request.hidden {
        let there = inside(hidden);
        if there.is_dir() {
            rustix::mount::mount(
                "raycast-hidden",
                &there,
                "tmpfs",
                MountFlags::RDONLY | MountFlags::NOSUID | MountFlags::NODEV | MountFlags::NOEXEC,
                c"size=4k,nr_inodes=1,mode=0",
            )
            .map_err(|e| failed("hiding", hidden, e.into()))?;
        }
    }
    let work = inside(&request.work);
    if request.work_kept {
        open_folder(&work, 0o755)?;
        rustix::mount::mount_bind_recursive(&request.work, &work)
            .map_err(|e| failed("binding", &request.work, e.into()))?;
    } else {
        copy_tree(&request.work, &work, request.user)?;
    }
    let outputs = inside(&request.outputs);
    if !outputs.exists() {
        open_folder(&outputs, 0o755)?;
        if let Some((uid, gid)) = request.user {
            std::os::unix::fs::chown(&outputs, Some(uid), Some(gid))
                .map_err(|e| failed("giving the renderer", &outputs, e))?;
        }
    }
    let real_outputs = rustix::fs::open(
        &request.outputs,
        OFlags::DIRECTORY | OFlags::RDONLY | OFlags::CLOEXEC,
        Mode::empty(),
    )
    .map_err(|e| failed("opening", &request.outputs, e.into()))?;
    let old = root.join(".old");
    fs::create_dir(&old).map_err(|e| failed("making", &old, e))?;
    rustix::process::pivot_root(root, &old)
        .map_err(|e| failed("moving the root to", root, e.into()))?;
    rustix::process::chdir("/").map_err(|e| format!("entering the new root: {e}"))?;
    rustix::mount::unmount("/.old", UnmountFlags::DETACH)
        .map_err(|e| format!("leaving the old root: {e}"))?;
    let _ = fs::remove_dir("/.old");
    Ok(Root {
        outputs: real_outputs,
    })
}

impl Root {
    /// Copies the pictures the renderer left in its output folder (regular files of at most
    /// `largest` bytes) to the real output folder, where check grades them. What is not a
    /// plain file is given back as what it is, empty (a link with its target's name, a folder,
    /// a pipe for a pipe, socket or device), so that check names it; nothing is followed.
    /// Called once nothing of the renderer's runs.
    pub fn give_back_pictures(&self, outputs: &Path, largest: u64) {
        use rustix::fs::FileType;
        let Ok(entries) = fs::read_dir(outputs) else {
            return;
        };
        let into = self.outputs.as_fd();
        for entry in entries.flatten() {
            let Ok(metadata) = fs::symlink_metadata(entry.path()) else {
                continue;
            };
            let name = entry.file_name();
            let kind = metadata.file_type();
            let _: io::Result<()> = if kind.is_file() && metadata.len() <= largest {
                copy_out(&entry.path(), &name, into)
            } else if kind.is_symlink() {
                fs::read_link(entry.path())
                    .and_then(|target| Ok(rustix::fs::symlinkat(target, into, &name)?))
            } else if kind.is_dir() {
                rustix::fs::mkdirat(into, &name, Mode::from_raw_mode(0o755)).map_err(Into::into)
            } else if !kind.is_file() {
                let mode = Mode::from_raw_mode(0o644);
                rustix::fs::mknodat(into, &name, FileType::Fifo, mode, 0).map_err(Into::into)
            } else {
                Ok(())
            };
        }
    }
}

/// Copies `from` into the folder `into` as `name`: a new file, never through a link.
fn copy_out(from: &Path, name: &std::ffi::OsStr, into: impl AsFd) -> io::Result<()> {
    let mut source = fs::File::open(from)?;
    let target = rustix::fs::openat(
        into,
        name,
        OFlags::WRONLY | OFlags::CREATE | OFlags::EXCL | OFlags::NOFOLLOW | OFlags::CLOEXEC,
        Mode::from_raw_mode(0o644),
    )?;
    io::copy(&mut source, &mut fs::File::from(target))?;
    Ok(())
}

/// Makes `path` (and what is missing above it) in the new root, with `mode` for the last.
fn open_folder(path: &Path, mode: u32) -> Result<(), String> {
    fs::DirBuilder::new()
        .recursive(true)
        .mode(0o755)
        .create(path)
        .and_then(|()| fs::set_permissions(path, fs::Permissions::from_mode(mode)))
        .map_err(|e| format!("making {}: {e}", path.display()))
}

/// Binds `source` (a folder or a file, with what is mounted below it) at `target` in the new
/// root, read-only.
fn bind_read_only(source: &Path, target: &Path) -> Result<(), String> {
    let metadata =
        fs::metadata(source).map_err(|e| format!("reading {}: {e}", source.display()))?;
    if metadata.is_dir() {
        open_folder(target, 0o755)?;
    } else {
        if let Some(parent) = target.parent() {
            open_folder(parent, 0o755)?;
        }
        fs::write(target, b"").map_err(|e| format!("making {}: {e}", target.display()))?;
    }
    rustix::mount::mount_bind_recursive(source, target)
        .map_err(|e| format!("binding {} on {}: {e}", source.display(), target.display()))?;
    read_only(target)
}

/// Makes the mount at `target`, and every mount below it, read-only, without set-user-ID
/// programs or devices (`mount_setattr`, Linux 5.12; where it is missing, the top mount alone,
/// keeping the flags the machine locked on it).
fn read_only(target: &Path) -> Result<(), String> {
    if mount_setattr_read_only(target).is_ok() {
        return Ok(());
    }
    let locked = rustix::fs::statvfs(target)
        .map(|s| s.f_flag)
        .map_err(|e| format!("reading the mount of {}: {e}", target.display()))?;
    let mut flags = MountFlags::BIND | MountFlags::RDONLY | MountFlags::NOSUID | MountFlags::NODEV;
    if locked.contains(rustix::fs::StatVfsMountFlags::NOEXEC) {
        flags |= MountFlags::NOEXEC;
    }
    rustix::mount::mount_remount(target, flags, "")
        .map_err(|e| format!("making {} read-only: {e}", target.display()))
}

/// `mount_setattr(target, AT_RECURSIVE, {RDONLY | NOSUID | NODEV})`: rustix has no wrapper.
#[allow(unsafe_code)]
fn mount_setattr_read_only(target: &Path) -> io::Result<()> {
    #[repr(C)]
    struct MountAttr {
        attr_set: u64,
        attr_clr: u64,
        propagation: u64,
        userns_fd: u64,
    }
    const MOUNT_ATTR_RDONLY: u64 = 0x1;
    const MOUNT_ATTR_NOSUID: u64 = 0x2;
    const MOUNT_ATTR_NODEV: u64 = 0x4;
    const AT_RECURSIVE: libc::c_uint = 0x8000;
    let path = std::ffi::CString::new(target.as_os_str().as_encoded_bytes())
        .map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
    let attr = MountAttr {
        attr_set: MOUNT_ATTR_RDONLY | MOUNT_ATTR_NOSUID | MOUNT_ATTR_NODEV,
        attr_clr: 0,
        propagation: 0,
        userns_fd: 0,
    };
    // SAFETY: `path` is a NUL-terminated string and `attr` a mount_attr of the size passed,
    // both alive for the call; the kernel only reads them.
    let result = unsafe {
        libc::syscall(
            libc::SYS_mount_setattr,
            libc::AT_FDCWD,
            path.as_ptr(),
            AT_RECURSIVE,
            &attr as *const MountAttr,
            std::mem::size_of::<MountAttr>(),
        )
    };
    if result == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

/// The devices of the new root's /dev (each bound from the machine's), and the links programs
/// expect there.
fn make_devices(dev: &Path) -> Result<(), String> {
    open_folder(dev, 0o755)?;
    for device in DEVICES {
        let source = Path::new("/dev").join(device);
        if !source.exists() {
            continue;
        }
        let target = dev.join(device);
        fs::write(&target, b"").map_err(|e| format!("making {}: {e}", target.display()))?;
        rustix::mount::mount_bind(&source, &target)
            .map_err(|e| format!("binding {}: {e}", source.display()))?;
    }
    for (name, target) in [
        ("fd", "/proc/self/fd"),
        ("stdin", "/proc/self/fd/0"),
        ("stdout", "/proc/self/fd/1"),
        ("stderr", "/proc/self/fd/2"),
    ] {
        std::os::unix::fs::symlink(target, dev.join(name))
            .map_err(|e| format!("linking /dev/{name}: {e}"))?;
    }
    Ok(())
}

/// Copies the line's prepared work folder (the scene's files, a home and a temporary folder)
/// into the new root, owned by the renderer's user where one is given.
fn copy_tree(from: &Path, to: &Path, user: Option<(u32, u32)>) -> Result<(), String> {
    let failed = |path: &Path, e: io::Error| format!("copying {}: {e}", path.display());
    let metadata = fs::symlink_metadata(from).map_err(|e| failed(from, e))?;
    if metadata.is_dir() {
        open_folder(to, metadata.permissions().mode() & 0o7777)?;
        for entry in fs::read_dir(from).map_err(|e| failed(from, e))? {
            let entry = entry.map_err(|e| failed(from, e))?;
            copy_tree(&entry.path(), &to.join(entry.file_name()), user)?;
        }
    } else if metadata.is_file() {
        fs::copy(from, to).map_err(|e| failed(from, e))?;
    } else {
        return Ok(());
    }
    if let Some((uid, gid)) = user {
        std::os::unix::fs::chown(to, Some(uid), Some(gid)).map_err(|e| failed(to, e))?;
    }
    Ok(())
}
