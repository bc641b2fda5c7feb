//! The course's interactive preview (`-gui`), in the browser: raycast serves a page on
//! loopback that draws the scene as the staff's OpenGL viewer does (WebGL2 emulating its
//! fixed-function lighting), moves the camera with the mouse as the staff's viewer does, and
//! redraws when the scene file or a mesh it names changes on disk.
//!
//! - `drawing.rs`: the scene as the viewer draws it (tessellated, lit per vertex);
//! - `server.rs`: the HTTP server, its token and Host checks, and its event streams;
//! - `watch.rs`: re-reading the scene when its files change;
//! - `view.rs`: the page's view traced by raycast: 'r' renders it, 't' one pixel's ray tree;
//! - `page/`: the page and its script, built into the binary.

mod drawing;
mod server;
mod view;
mod watch;

use std::io::Write;
use std::sync::Arc;
use std::sync::atomic::Ordering;

pub use drawing::{
    DEFAULT_TESSELLATION, Drawing, MAX_LIGHTS, PLANE_HALF_SIDE, Tessellation, camera_json, draw,
};
pub use server::{PreviewServer, Shown, is_loopback_host};
pub use view::{
    Rendered, camera_of, camera_text, grid, grid_walk, ray_tree, render_view, scene_at,
};

use crate::error::Error;
use crate::job::Options;
use crate::parse::description::SceneDescription;

/// The environment variable that fixes the preview's token (otherwise random), so that a tab
/// left open reconnects when raycast is started again on the same port.
pub const TOKEN_VARIABLE: &str = "RAYCAST_PREVIEW_TOKEN";

/// How the preview draws the line's scene.
pub fn tessellation(options: &Options) -> Tessellation {
    Tessellation {
        steps: options.preview.tessellation.unwrap_or(DEFAULT_TESSELLATION),
        gouraud: options.preview.gouraud,
    }
}

/// Reads the scene as the preview shows it: the drawing's description for the page (with the
/// line's size and switches) and its vertices.
pub fn read(options: &Options) -> Result<(String, Vec<u8>), Error> {
    let description = crate::parse::read_scene(&options.input)?;
    // The same checks as a render's, so that the page shows the error the command line would.
    crate::scene::Scene::from_description(&description)?;
    drawn(options, &description)
}

fn drawn(options: &Options, description: &SceneDescription) -> Result<(String, Vec<u8>), Error> {
    let Drawing {
        vertices, mut meta, ..
    } = draw(description, tessellation(options))?;
    meta["width"] = options.width.into();
    meta["height"] = options.height.into();
    meta["specular_fix"] = (options.trace.specular == crate::scene::SpecularFalloff::Fade).into();
    meta["gouraud"] = options.preview.gouraud.into();
    meta["visualize_grid"] = (options.trace.visualize_grid && options.grid.is_some()).into();
    meta["tessellation"] = serde_json::json!(tessellation(options).steps);
    Ok((meta.to_string(), vertices))
}

/// Serves the preview of the line's scene until the page's 'q' or Ctrl-C: prints the address
/// first on `out`, then calls `started` (which writes the line's images), then opens the
/// browser unless `-no-browser`.
pub fn serve(
    options: &Options,
    out: &mut dyn Write,
    started: impl FnOnce() -> Result<(), Error>,
) -> Result<(), Error> {
    let (meta, vertices, error) = match read(options) {
        Ok((meta, vertices)) => (meta, vertices, None),
        Err(error) => (String::new(), Vec::new(), Some(error.to_string())),
    };
    let shown = Shown {
        version: 1,
        meta,
        vertices: Arc::new(vertices),
        error,
        camera: None,
    };
    let token = match std::env::var(TOKEN_VARIABLE) {
        Ok(token) if token.len() >= 16 && token.bytes().all(|b| b.is_ascii_alphanumeric()) => token,
        Ok(_) => {
            return Err(Error::Preview(format!(
                "{TOKEN_VARIABLE} must be at least 16 letters and digits"
            )));
        }
        Err(_) => random_token()?,
    };
    let port = options.preview.port.unwrap_or(0);
    let server = PreviewServer::bind(port, token, shown, options).map_err(Error::Preview)?;
    let quit = server.quit_flag();
    // Ctrl-C ends the preview as 'q' does: exit 0. Only one handler may be set per process.
    // Set before the address is printed: whoever reads it may press Ctrl-C at once.
    let on_interrupt = quit.clone();
    ctrlc::set_handler(move || on_interrupt.store(true, Ordering::SeqCst)).ok();
    writeln!(out, "{}", server.url())
        .and_then(|()| out.flush())
        .ok();
    watch::watch(options, server.shown(), server.announcer())?;
    started()?;
    if !options.preview.no_browser && webbrowser::open(&server.url()).is_err() {
        eprintln!("raycast: could not open a browser: open the address above");
    }
    server.run();
    Ok(())
}

/// 128 random bits from the operating system, as 32 hex digits.
fn random_token() -> Result<String, Error> {
    use std::io::Read;
    let mut bytes = [0u8; 16];
    std::fs::File::open("/dev/urandom")
        .and_then(|mut f| f.read_exact(&mut bytes))
        .map_err(|e| Error::Preview(format!("cannot make the preview's token: {e}")))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}
