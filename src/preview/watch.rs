//! Re-reading the scene when its files change: the folders of the scene file and of every mesh
//! it names are watched (editors save by writing a new file and renaming it over the old one,
//! which a watch on the file itself would lose), and each change to one of those files, once
//! the writes settle, makes the preview read the scene again: the pages redraw it, or show its
//! error while keeping the last good scene drawn.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use notify::{EventKind, RecommendedWatcher, RecursiveMode, Watcher};

use super::server::{Announcer, Shown};
use crate::error::Error;
use crate::job::Options;
use crate::parse::description::Shape;

/// How long the files must stay still before the scene is read again: an editor's save is a
/// burst of events.
const SETTLE: Duration = Duration::from_millis(60);

/// Watches the line's scene and meshes for as long as the process runs; each change re-reads
/// them into `shown` and tells the pages through `announcer`.
pub fn watch(
    options: &Options,
    shown: Arc<Mutex<Shown>>,
    announcer: Announcer,
) -> Result<(), Error> {
    let (send, receive) = channel();
    let mut watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
        // Reading the files (as each reload does) makes access events: only changes count.
        if let Ok(event) = event
            && matches!(
                event.kind,
                EventKind::Create(_) | EventKind::Modify(_) | EventKind::Remove(_)
            )
        {
            send.send(event.paths).ok();
        }
    })
    .map_err(|e| Error::Preview(format!("cannot watch the scene's files: {e}")))?;
    let files = Arc::new(Mutex::new(watched_files(options)));
    let mut folders = BTreeSet::new();
    for file in files.lock().expect("not poisoned").iter() {
        follow(&mut watcher, &mut folders, file);
    }
    let options = options.clone();
    std::thread::spawn(move || {
        loop {
            let Ok(paths) = receive.recv() else { return };
            let mut touched = concerns(&files, &paths);
            // Let the burst settle, collecting whether any of it concerns the scene.
            loop {
                match receive.recv_timeout(SETTLE) {
                    Ok(paths) => touched |= concerns(&files, &paths),
                    Err(RecvTimeoutError::Timeout) => break,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            }
            if !touched {
                continue;
            }
            let now = watched_files(&options);
            for file in &now {
                follow(&mut watcher, &mut folders, file);
            }
            *files.lock().expect("not poisoned") = now;
            reload(&options, &shown, &announcer);
        }
    });
    Ok(())
}

/// Reads the scene again into `shown` and tells the pages: the new scene, or the error.
fn reload(options: &Options, shown: &Mutex<Shown>, announcer: &Announcer) {
    match super::read(options) {
        Ok((meta, vertices)) => {
            let version = {
                let mut shown = shown.lock().expect("not poisoned");
                shown.version += 1;
                shown.meta = meta;
                shown.vertices = Arc::new(vertices);
                shown.error = None;
                shown.version
            };
            announcer.announce("scene", &version.to_string());
        }
        Err(error) => {
            let message = error.to_string();
            let version = {
                let mut shown = shown.lock().expect("not poisoned");
                shown.error = Some(message.clone());
                shown.version
            };
            announcer.announce("scene", &version.to_string());
        }
    }
}

/// Whether any of `paths` is one of the scene's files.
fn concerns(files: &Mutex<BTreeSet<PathBuf>>, paths: &[PathBuf]) -> bool {
    let files = files.lock().expect("not poisoned");
    paths.iter().any(|p| files.contains(&absolute(p)))
}

/// The scene file and the mesh files it names (as far as it reads).
fn watched_files(options: &Options) -> BTreeSet<PathBuf> {
    let mut files = BTreeSet::from([absolute(&options.input)]);
    if let Ok(description) = crate::parse::read_scene(&options.input) {
        for object in &description.objects {
            if let Shape::Mesh { file } = &object.shape {
                let beside = options.input.parent().unwrap_or(Path::new("")).join(file);
                files.insert(absolute(&beside));
                files.insert(absolute(Path::new(file)));
            }
        }
    }
    files
}

/// Watches the folder of `file`, once.
fn follow(watcher: &mut RecommendedWatcher, folders: &mut BTreeSet<PathBuf>, file: &Path) {
    let Some(folder) = file.parent() else { return };
    if folders.insert(folder.to_path_buf()) {
        // A folder that does not exist (a mesh named wrongly) is watched once it is named again.
        if watcher.watch(folder, RecursiveMode::NonRecursive).is_err() {
            folders.remove(folder);
        }
    }
}

/// `path` from the root, its folder's links resolved (the watcher reports resolved paths).
fn absolute(path: &Path) -> PathBuf {
    let joined = std::env::current_dir()
        .map(|d| d.join(path))
        .unwrap_or_else(|_| path.to_path_buf());
    match (joined.parent(), joined.file_name()) {
        (Some(folder), Some(name)) => folder
            .canonicalize()
            .map(|f| f.join(name))
            .unwrap_or(joined),
        _ => joined,
    }
}
