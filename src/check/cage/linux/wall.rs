//! No stranger's program is graded without a wall that is known to hold: before any line runs,
//! check finds out whether the renderer will be kept from the suite's references and from
//! writing outside its folders, and refuses to grade where nothing would (unless told
//! `--no-cage`, which every report then records).

use std::path::Path;

use super::{Request, confine, reachable_by_others};

/// What keeps a renderer from the references, as found before any line runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Wall {
    /// Landlock's state on this kernel, as the supervisor reports it.
    pub landlock: String,
    /// The system folder the suite lies in (which every renderer may read), if any.
    pub suite_in_system: Option<String>,
    /// Whether the renderer runs as another user (check runs as root) who cannot read the
    /// references.
    pub references_out_of_reach: bool,
    /// Whether a line gets a root of its own here (the suite hidden in it, its writes on its
    /// own tmpfs), as a probe line found; if not, why not.
    pub own_root: Result<(), String>,
}

impl Wall {
    /// The wall for `suite`, on this machine, for a check running as root or not.
    pub fn find(suite: &Path, root: bool) -> Wall {
        let suite = std::fs::canonicalize(suite).unwrap_or_else(|_| suite.to_path_buf());
        // One probe line tells both: Landlock's state and whether a line gets its own root.
        let probe = probe(&suite);
        Wall {
            landlock: match &probe {
                Ok(cage) => cage.landlock.clone(),
                Err(why) => format!("not tried ({why})"),
            },
            own_root: probe.and_then(|cage| cage.own_root),
            suite_in_system: confine::SYSTEM
                .iter()
                .find(|folder| suite.starts_with(folder))
                .map(|folder| folder.to_string()),
            references_out_of_reach: root && reachable_by_others(&suite.join("reference")).is_err(),
        }
    }

    /// Whether Landlock holds the renderer to its folders on this kernel.
    fn landlock_holds(&self) -> bool {
        self.landlock.starts_with("fully") || self.landlock.starts_with("partially")
    }

    /// `Ok` where at least one wall keeps the references from the renderer and its writes in
    /// its folders; else why not, and how to get one. On Linux a wall is asked of every check,
    /// one's own renderer's as much as `others`' (a class's): one can be had on any kernel of
    /// the last years, or `--no-cage` said.
    pub fn holds(&self, others: bool) -> Result<(), String> {
        let _ = others;
        if self.references_out_of_reach || self.own_root.is_ok() {
            return Ok(());
        }
        if self.landlock_holds() {
            return match &self.suite_in_system {
                None => Ok(()),
                Some(folder) => Err(format!(
                    "the suite lies under {folder}, which every renderer may read (the system's \
                     folders are open to it), so its references would be the renderer's to copy: \
                     keep the suite in a folder of your own (your home, /srv), or give --no-cage \
                     to grade anyway"
                )),
            };
        }
        let own_root = self.own_root.as_ref().err().map_or("", String::as_str);
        Err(format!(
            "nothing here keeps a renderer from the suite's references and from writing outside \
             its folders: a line gets no root of its own ({own_root}; it needs user and mount \
             namespaces: as root, or with unprivileged user namespaces allowed, and in a \
             container the CAP_SYS_ADMIN capability or a seccomp profile that allows unshare and \
             mount), and Landlock is {} (it needs Linux 5.13 or later with landlock among the \
             kernel's security modules, and in a container a seccomp profile that allows the \
             landlock system calls). Grading your own renderer on your own machine, give \
             --no-cage; never grade other people's programs without a cage",
            self.landlock
        ))
    }
}

/// Runs a line with nothing to run, to see what its cage holds (Landlock, a root of its own
/// with the suite hidden): the cage's own verdict, on this machine, before any stranger's code
/// runs.
fn probe(suite: &Path) -> Result<super::Confinement, String> {
    let folder = tempfile::tempdir().map_err(|e| format!("no scratch folder: {e}"))?;
    let [work, outputs, root] = ["work", "out", "root"].map(|name| folder.path().join(name));
    for made in [&work, &outputs, &root] {
        std::fs::create_dir(made).map_err(|e| format!("{}: {e}", made.display()))?;
    }
    let probe = Request {
        command: Vec::new(),
        work,
        outputs,
        readable: Vec::new(),
        hidden: vec![suite.to_path_buf()],
        root: Some(root),
        work_kept: false,
        limit: std::time::Duration::from_secs(5),
        limits: super::Limits::default(),
        user: None,
        held: false,
    };
    super::run(&probe, &crate::render::StopFlag::default())
        .confinement
        .ok_or_else(|| "the probe line's supervisor said nothing".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(landlock: &str, system: Option<&str>, out_of_reach: bool) -> Wall {
        Wall {
            landlock: landlock.into(),
            suite_in_system: system.map(String::from),
            references_out_of_reach: out_of_reach,
            own_root: Err("no mount namespace: Operation not permitted".into()),
        }
    }

    #[test]
    fn a_wall_must_hold_before_a_stranger_is_graded() {
        assert!(wall("fully enforced", None, false).holds(true).is_ok());
        assert!(
            wall("partially enforced (an older kernel)", None, false)
                .holds(true)
                .is_ok()
        );
        // Landlock lets a renderer read the system's folders: a suite there gives its
        // references away.
        let under_opt = wall("fully enforced", Some("/opt"), false)
            .holds(true)
            .unwrap_err();
        assert!(under_opt.starts_with("the suite lies under /opt, which every renderer may read"));
        // Another user who cannot read the references holds, with or without Landlock.
        assert!(
            wall("fully enforced", Some("/opt"), true)
                .holds(true)
                .is_ok()
        );
        assert!(
            wall("not available on this kernel", None, true)
                .holds(true)
                .is_ok()
        );
        let none = wall("not available on this kernel", None, false)
            .holds(true)
            .unwrap_err();
        assert!(
            none.contains("Landlock is not available on this kernel"),
            "{none}"
        );
        assert!(none.contains("give --no-cage"), "{none}");
        assert!(
            none.contains("a line gets no root of its own (no mount namespace"),
            "{none}"
        );
        // A root of its own hides the suite wherever it lies, with Landlock or without.
        let own = Wall {
            own_root: Ok(()),
            ..wall("not available on this kernel", Some("/opt"), false)
        };
        assert!(own.holds(true).is_ok());
    }

    #[test]
    fn the_suite_in_a_system_folder_is_found() {
        assert_eq!(
            Wall::find(Path::new("/usr/share"), false).suite_in_system,
            Some("/usr".to_string())
        );
        let own = tempfile::tempdir().unwrap();
        assert_eq!(Wall::find(own.path(), false).suite_in_system, None);
    }
}
