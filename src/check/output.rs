//! Reading pictures: the suite's references (any image raycast reads), and what a renderer
//! wrote, which is hostile until read: no links, no FIFOs, no more bytes than a picture of its
//! reference's size takes, the size in its header checked before a pixel is decoded, and the
//! format its name says.

use std::io::{Cursor, Read};
use std::path::Path;

use super::Diagnosis;
use crate::shade::Image;

/// The largest image file `check` reads: anything bigger is not a picture of the course.
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;

/// Why a renderer's picture cannot be graded: the cause, and what to tell the student.
#[derive(Debug, Clone, PartialEq)]
pub struct Unread {
    /// `missing_output`, `unreadable_output`, `output_too_large`, `wrong_format` or `size`.
    pub cause: Diagnosis,
    /// What was found, in a sentence.
    pub message: String,
}

fn unread(cause: Diagnosis, message: impl Into<String>) -> Unread {
    Unread {
        cause,
        message: message.into(),
    }
}

/// Reads an image file, whatever it is: refused when missing, too big, or not a picture in a
/// format raycast reads (TGA, PPM, PNG).
pub fn read_image(path: &Path) -> Result<Image, String> {
    let file = open_plain(path, true).map_err(|u| u.message)?;
    let mut bytes = Vec::new();
    file.take(MAX_IMAGE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("The image cannot be read: {e}"))?;
    if bytes.len() as u64 > MAX_IMAGE_BYTES {
        return Err("The image is far too big to be one of the course's".into());
    }
    let format = signature(&bytes)
        .or_else(|| image::ImageFormat::from_path(path).ok())
        .ok_or("The file is not a picture in a format raycast reads (TGA, PPM, PNG)")?;
    decode(&bytes, format, 1 << 30).map_err(|u| u.message)
}

/// Reads what a renderer wrote at `path` as a picture of `size` (its reference's width and
/// height).
pub fn read_output(path: &Path, size: (u32, u32)) -> Result<Image, Unread> {
    let file = open_plain(path, false)?;
    // Any of the course's formats, even text PPM at 12 bytes a pixel, fits in this.
    let pixels = u64::from(size.0) * u64::from(size.1);
    let most = (16 * pixels + (1 << 20)).min(MAX_IMAGE_BYTES);
    let length = file.metadata().map(|m| m.len()).unwrap_or(0);
    if length > most {
        return Err(unread(
            Diagnosis::OUTPUT_TOO_LARGE,
            format!(
                "The image is {length} bytes, far more than a {}x{} picture takes",
                size.0, size.1
            ),
        ));
    }
    let mut bytes = Vec::new();
    file.take(most + 1).read_to_end(&mut bytes).map_err(|e| {
        unread(
            Diagnosis::UNREADABLE_OUTPUT,
            format!("The image cannot be read: {e}"),
        )
    })?;
    let named = image::ImageFormat::from_path(path).ok();
    let format = match (named, signature(&bytes)) {
        (Some(named), Some(held)) if named != held => {
            return Err(unread(
                Diagnosis::WRONG_FORMAT,
                format!(
                    "The file is named .{} but holds a {} picture",
                    extension(path),
                    format_name(held)
                ),
            ));
        }
        (_, Some(held)) => held,
        (Some(named), None) => named,
        (None, None) => {
            return Err(unread(
                Diagnosis::UNREADABLE_OUTPUT,
                "The file is not a picture in a format raycast reads (TGA, PPM, PNG)",
            ));
        }
    };
    let header = image::ImageReader::with_format(Cursor::new(&bytes), format)
        .into_dimensions()
        .map_err(|e| {
            unread(
                Diagnosis::UNREADABLE_OUTPUT,
                format!("The file is not a readable image: {e}"),
            )
        })?;
    if header != size {
        return Err(unread(
            Diagnosis::SIZE,
            format!(
                "The picture is {}x{}; its reference is {}x{}",
                header.0, header.1, size.0, size.1
            ),
        ));
    }
    // Decoding may take up to 8 bytes a pixel (16-bit RGBA) and its RGB copy.
    decode(&bytes, format, 16 * pixels + (1 << 20))
}

/// The format a file's first bytes announce; TGA has no signature.
fn signature(bytes: &[u8]) -> Option<image::ImageFormat> {
    match bytes {
        [0x89, b'P', b'N', b'G', ..] => Some(image::ImageFormat::Png),
        [b'P', b'1'..=b'7', ..] => Some(image::ImageFormat::Pnm),
        _ => None,
    }
}

fn format_name(format: image::ImageFormat) -> &'static str {
    match format {
        image::ImageFormat::Png => "PNG",
        image::ImageFormat::Pnm => "PPM",
        image::ImageFormat::Tga => "TGA",
        _ => "different",
    }
}

fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn decode(bytes: &[u8], format: image::ImageFormat, most: u64) -> Result<Image, Unread> {
    let mut reader = image::ImageReader::with_format(Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(crate::image_io::MAX_SIDE);
    limits.max_image_height = Some(crate::image_io::MAX_SIDE);
    limits.max_alloc = Some(most);
    reader.limits(limits);
    let decoded = reader
        .decode()
        .map_err(|e| {
            unread(
                Diagnosis::UNREADABLE_OUTPUT,
                format!("The file is not a readable image: {e}"),
            )
        })?
        .to_rgb8();
    Ok(Image {
        width: decoded.width(),
        height: decoded.height(),
        pixels: decoded.pixels().map(|p| p.0).collect(),
    })
}

/// Opens `path` for reading only if it is a plain file, without blocking on a FIFO (which
/// would hang the check); unless `follow_links`, not through a symbolic link either.
fn open_plain(path: &Path, follow_links: bool) -> Result<std::fs::File, Unread> {
    let mut open = std::fs::OpenOptions::new();
    open.read(true);
    // Windows has no FIFOs in the file system, and the link is refused below before opening.
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let mut flags = rustix::fs::OFlags::NONBLOCK;
        if !follow_links {
            flags |= rustix::fs::OFlags::NOFOLLOW;
        }
        open.custom_flags(flags.bits() as i32);
    }
    let kind = std::fs::symlink_metadata(path).map(|m| m.file_type());
    if !follow_links && kind.as_ref().is_ok_and(|k| k.is_symlink()) {
        return Err(unread(
            Diagnosis::UNREADABLE_OUTPUT,
            "The image is a symbolic link: raycast reads only plain files",
        ));
    }
    let file = open.open(path).map_err(|e| match kind {
        Ok(_) => unread(
            Diagnosis::UNREADABLE_OUTPUT,
            format!("The image cannot be opened: {e}"),
        ),
        Err(_) => unread(
            Diagnosis::MISSING_OUTPUT,
            format!("There is no image '{}'", path.display()),
        ),
    })?;
    let is_file = file.metadata().map(|m| m.is_file()).unwrap_or(false);
    if !is_file {
        return Err(unread(
            Diagnosis::UNREADABLE_OUTPUT,
            "The image is not a plain file (a FIFO, a folder or a device): raycast reads only \
             plain files",
        ));
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }

    #[test]
    fn a_renderers_picture_is_checked_before_it_is_decoded() {
        let dir = tempfile::tempdir().unwrap();
        let image = Image {
            width: 4,
            height: 2,
            pixels: vec![[10, 20, 30]; 8],
        };
        let png = crate::image_io::encode(&image, crate::image_io::ImageFormat::Png);
        let tga = crate::image_io::encode(&image, crate::image_io::ImageFormat::Tga);
        let cause = |r: Result<Image, Unread>| r.map(|_| ()).map_err(|u| u.cause.code());
        assert_eq!(
            read_output(&written(dir.path(), "a.png", &png), (4, 2)),
            Ok(image.clone())
        );
        assert_eq!(
            read_output(&written(dir.path(), "a.tga", &tga), (4, 2)),
            Ok(image)
        );
        let wrong = read_output(&written(dir.path(), "b.tga", &png), (4, 2)).unwrap_err();
        assert_eq!(wrong.cause, Diagnosis::WRONG_FORMAT);
        assert_eq!(
            wrong.message,
            "The file is named .tga but holds a PNG picture"
        );
        let size = read_output(&written(dir.path(), "c.png", &png), (200, 200)).unwrap_err();
        assert_eq!(size.message, "The picture is 4x2; its reference is 200x200");
        assert_eq!(size.cause, Diagnosis::SIZE);
        let huge = written(dir.path(), "d.tga", &vec![0; 2 << 20]);
        assert_eq!(cause(read_output(&huge, (4, 2))), Err("output_too_large"));
        let cut = written(dir.path(), "e.png", &png[..png.len() / 2]);
        assert_eq!(cause(read_output(&cut, (4, 2))), Err("unreadable_output"));
        assert_eq!(
            cause(read_output(&dir.path().join("none.tga"), (4, 2))),
            Err("missing_output")
        );
    }
}
