//! A low integrity level for the renderer, where Windows lets an ordinary user give one (no
//! administrator's rights are needed to lower a level, only to raise it). A process at low
//! integrity cannot write to anything labelled above it, and every file and folder without a
//! label is medium: the user's documents, their projects, the suite, the registry's user hive.
//! So the supervisor labels the line's own folders low (the one place the renderer writes),
//! then lowers its own level, which the renderer inherits. Reads are untouched (a low process
//! may read what its user may), which is why Windows' cage is still not enough for other
//! people's programs.

use std::ffi::OsStr;
use std::os::windows::ffi::OsStrExt;
use std::os::windows::io::{AsRawHandle, FromRawHandle, OwnedHandle};
use std::path::Path;

use windows_sys::Win32::Foundation::{ERROR_SUCCESS, HANDLE, HLOCAL, LocalFree};
use windows_sys::Win32::Security::Authorization::{
    ConvertStringSecurityDescriptorToSecurityDescriptorW, ConvertStringSidToSidW, SDDL_REVISION_1,
    SE_FILE_OBJECT, SetNamedSecurityInfoW,
};
use windows_sys::Win32::Security::{
    ACL, GetLengthSid, GetSecurityDescriptorSacl, LABEL_SECURITY_INFORMATION, PSECURITY_DESCRIPTOR,
    PSID, SID_AND_ATTRIBUTES, SetTokenInformation, TOKEN_ADJUST_DEFAULT, TOKEN_MANDATORY_LABEL,
    TOKEN_QUERY, TokenIntegrityLevel,
};
use windows_sys::Win32::System::Threading::{GetCurrentProcess, OpenProcessToken};

/// The low mandatory label, inherited by every file and folder made inside, and forbidding
/// writes from below it (none is below low but untrusted).
const LOW_LABEL: &str = "S:(ML;OICI;NW;;;LW)";
/// The low integrity level's SID.
const LOW_LEVEL: &str = "S-1-16-4096";
/// SE_GROUP_INTEGRITY: the SID is an integrity level.
const INTEGRITY: u32 = 0x20;

fn wide(text: &OsStr) -> Vec<u16> {
    text.encode_wide().chain(std::iter::once(0)).collect()
}

fn last_error(what: &str) -> String {
    format!("{what}: {}", std::io::Error::last_os_error())
}

/// Labels each of `folders` low, with what it holds and what will be made in it: a process at
/// low integrity may write there.
pub(super) fn open_to_low(folders: &[&Path]) -> Result<(), String> {
    let sddl = wide(OsStr::new(LOW_LABEL));
    let mut descriptor: PSECURITY_DESCRIPTOR = std::ptr::null_mut();
    // SAFETY: `sddl` is a NUL-ended wide string; the descriptor Windows allocates is freed
    // below, after its SACL (which points into it) was last used.
    unsafe {
        if ConvertStringSecurityDescriptorToSecurityDescriptorW(
            sddl.as_ptr(),
            SDDL_REVISION_1,
            &mut descriptor,
            std::ptr::null_mut(),
        ) == 0
        {
            return Err(last_error("the low label"));
        }
        let (mut present, mut defaulted) = (0, 0);
        let mut sacl: *mut ACL = std::ptr::null_mut();
        let mut labelled = if GetSecurityDescriptorSacl(
            descriptor,
            &mut present,
            &mut sacl,
            &mut defaulted,
        ) == 0
        {
            Err(last_error("the low label's list"))
        } else {
            Ok(())
        };
        for folder in folders {
            if labelled.is_err() {
                break;
            }
            let path = wide(folder.as_os_str());
            let status = SetNamedSecurityInfoW(
                path.as_ptr(),
                SE_FILE_OBJECT,
                LABEL_SECURITY_INFORMATION,
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                std::ptr::null(),
                sacl,
            );
            if status != ERROR_SUCCESS {
                labelled = Err(format!(
                    "labelling {} low: {}",
                    folder.display(),
                    std::io::Error::from_raw_os_error(status as i32)
                ));
            }
        }
        LocalFree(descriptor as HLOCAL);
        labelled
    }
}

/// Lowers this process's integrity level to low; what it starts next inherits it.
pub(super) fn lower_own_level() -> Result<(), String> {
    let level = wide(OsStr::new(LOW_LEVEL));
    // SAFETY: plain calls on this process's own token; the SID Windows allocates is freed
    // after the call that reads it, and the label structure lives across that call.
    unsafe {
        let mut raw: HANDLE = std::ptr::null_mut();
        if OpenProcessToken(
            GetCurrentProcess(),
            TOKEN_ADJUST_DEFAULT | TOKEN_QUERY,
            &mut raw,
        ) == 0
        {
            return Err(last_error("this process's token"));
        }
        let token = OwnedHandle::from_raw_handle(raw as _);
        let mut sid: PSID = std::ptr::null_mut();
        if ConvertStringSidToSidW(level.as_ptr(), &mut sid) == 0 {
            return Err(last_error("the low level's SID"));
        }
        let label = TOKEN_MANDATORY_LABEL {
            Label: SID_AND_ATTRIBUTES {
                Sid: sid,
                Attributes: INTEGRITY,
            },
        };
        let size = std::mem::size_of::<TOKEN_MANDATORY_LABEL>() as u32 + GetLengthSid(sid);
        let lowered = SetTokenInformation(
            token.as_raw_handle() as HANDLE,
            TokenIntegrityLevel,
            (&raw const label).cast(),
            size,
        );
        let result = if lowered == 0 {
            Err(last_error("lowering the integrity level"))
        } else {
            Ok(())
        };
        LocalFree(sid as HLOCAL);
        result
    }
}
