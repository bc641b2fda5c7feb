//! Pictures to files: TGA in the course's exact layout, binary PPM, and PNG, by extension.
//!
//! TGA and PPM are written here (a header and the bytes: the course's TGA layout, top-left origin
//! and BGR, is not what a general encoder picks); PNG goes through the `image` crate. Every file
//! is written to a temporary file beside its target and renamed into place only when all of a
//! run's files are complete, so a failed run leaves no partial image and touches no existing one.

use std::borrow::Cow;
use std::io::Write;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::Error;
use crate::shade::Image;

/// A picture file's format, chosen by the extension of its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// Uncompressed 24-bit Targa in the course's layout: top-left origin, B, G, R bytes.
    Tga,
    /// Binary PPM (P6).
    Ppm,
    /// PNG, encoded by the `image` crate.
    Png,
}

impl ImageFormat {
    /// The extensions [`ImageFormat::from_path`] knows, as a message lists them.
    pub const EXTENSIONS: &str = ".tga, .ppm or .png";

    /// The format a path's extension names, in any case; `None` for another extension or none.
    pub fn from_path(path: &Path) -> Option<ImageFormat> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "tga" => Some(ImageFormat::Tga),
            "ppm" => Some(ImageFormat::Ppm),
            "png" => Some(ImageFormat::Png),
            _ => None,
        }
    }
}

/// The whole file for `image` in `format`, as one buffer.
pub fn encode(image: &Image, format: ImageFormat) -> Vec<u8> {
    encode_parts(image, format).into_vec()
}

/// A picture file's bytes, in the pieces they are written in: a PPM's pixels go out straight
/// from the picture (a 4096² picture is 50 MB, and copying it behind a header took longer than
/// writing it).
pub struct Encoded<'a> {
    parts: [Cow<'a, [u8]>; 2],
}

impl Encoded<'_> {
    /// The file's length in bytes.
    pub fn size(&self) -> u64 {
        self.parts.iter().map(|part| part.len() as u64).sum()
    }

    /// Writes the file's bytes to `out`.
    pub fn write_to(&self, out: &mut impl Write) -> std::io::Result<()> {
        self.parts.iter().try_for_each(|part| out.write_all(part))
    }

    /// The file's bytes in one buffer.
    pub fn into_vec(self) -> Vec<u8> {
        let [head, rest] = self.parts;
        let mut bytes = head.into_owned();
        bytes.extend_from_slice(&rest);
        bytes
    }
}

/// The file for `image` in `format`. A TGA's sides must be at most [`TGA_MAX_SIDE`] (the
/// command line sees to that).
pub fn encode_parts(image: &Image, format: ImageFormat) -> Encoded<'_> {
    let (w, h) = (image.width, image.height);
    let parts = match format {
        ImageFormat::Tga => {
            let mut header = Vec::with_capacity(18);
            // Uncompressed true colour (type 2), 24 bits, descriptor 32: rows top to bottom.
            header.extend_from_slice(&[0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
            header.extend_from_slice(&(w as u16).to_le_bytes());
            header.extend_from_slice(&(h as u16).to_le_bytes());
            header.extend_from_slice(&[24, 32]);
            // Zeroed by the allocator, page by page as the threads fill them.
            let mut body = vec![0_u8; image.pixels.len() * 3];
            const ROW: usize = 4096;
            body.par_chunks_mut(3 * ROW)
                .zip(image.pixels.par_chunks(ROW))
                .for_each(|(out, pixels)| {
                    for (out, &[r, g, b]) in out.chunks_exact_mut(3).zip(pixels) {
                        out.copy_from_slice(&[b, g, r]);
                    }
                });
            [Cow::Owned(header), Cow::Owned(body)]
        }
        ImageFormat::Ppm => [
            Cow::Owned(format!("P6\n{w} {h}\n255\n").into_bytes()),
            Cow::Borrowed(image.pixels.as_flattened()),
        ],
        ImageFormat::Png => {
            use image::ImageEncoder;
            use image::codecs::png::{CompressionType, FilterType, PngEncoder};
            let mut bytes = Vec::new();
            let encoder = PngEncoder::new_with_quality(
                &mut bytes,
                CompressionType::Fast,
                FilterType::Adaptive,
            );
            encoder
                .write_image(
                    image.pixels.as_flattened(),
                    w,
                    h,
                    image::ExtendedColorType::Rgb8,
                )
                .expect("an in-memory PNG of a valid size cannot fail to encode");
            [Cow::Owned(bytes), Cow::Borrowed(&[][..])]
        }
    };
    Encoded { parts }
}

/// The folder a file is (to be) in: `.` for a bare file name.
pub(crate) fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    }
}

/// A TGA can say at most 65535 pixels a side.
pub const TGA_MAX_SIDE: u32 = u16::MAX as u32;

/// The largest side accepted, and the most pixels: about 270 million, which at 7 bytes a pixel
/// while rendering and up to three 3-byte pictures after is about 4.5 GB at the peak.
pub const MAX_SIDE: u32 = 32768;
/// See [`MAX_SIDE`].
pub const MAX_PIXELS: u64 = 1 << 28;
// Every size accepted fits a TGA header's 16-bit sides.
const _: () = assert!(MAX_SIDE <= TGA_MAX_SIDE);

/// Output files of one run, each reserved as a temporary file in its target's folder before the
/// render starts (so an unwritable folder is found before any work), and renamed into place
/// together by [`PendingOutputs::commit`]. Dropped uncommitted, they vanish.
pub struct PendingOutputs {
    files: Vec<(PathBuf, tempfile::NamedTempFile)>,
}

impl PendingOutputs {
    /// A temporary file beside each of `paths`, in their order; an error names the first that
    /// cannot be made (and those already made vanish).
    pub fn reserve(paths: &[&Path]) -> Result<PendingOutputs, Error> {
        let mut files = Vec::new();
        for &path in paths {
            let folder = folder_of(path);
            let mut builder = tempfile::Builder::new();
            builder.prefix(".raycast-").suffix(".part");
            // Temporary files are made private (0600) and the rename keeps that; an image is an
            // ordinary file and gets what any new file gets: 0666 less the user's umask.
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                builder.permissions(std::fs::Permissions::from_mode(0o666));
            }
            let file = builder.tempfile_in(folder).map_err(|e| Error::Write {
                path: path.to_path_buf(),
                // "Not found" also comes from folders that exist but take no files (/proc), so
                // the folder itself is asked before the message blames it.
                message: if !folder.exists() {
                    format!("the folder '{}' does not exist", folder.display())
                } else if !folder.is_dir() {
                    format!("'{}' is not a folder", folder.display())
                } else {
                    format!("cannot create a file in '{}': {e}", folder.display())
                },
            })?;
            files.push((path.to_path_buf(), file));
        }
        Ok(PendingOutputs { files })
    }

    /// Writes each file's bytes (in the order reserved), then renames them all into place.
    ///
    /// No fsync: the rename already guarantees that the process, however it stops, leaves the
    /// old file or the new one, never a mix; only a crash of the whole machine could lose the
    /// new image, and syncing took longer than tracing a million rays.
    pub fn commit(mut self, contents: &[Encoded]) -> Result<(), Error> {
        assert_eq!(
            self.files.len(),
            contents.len(),
            "one content for each reserved file"
        );
        for ((path, file), encoded) in self.files.iter_mut().zip(contents) {
            reserve_blocks(file.as_file(), encoded.size());
            encoded.write_to(file).map_err(|e| Error::Write {
                path: path.clone(),
                message: e.to_string(),
            })?;
        }
        for (path, file) in self.files {
            file.persist(&path).map_err(|e| Error::Write {
                path,
                message: e.error.to_string(),
            })?;
        }
        Ok(())
    }
}

/// Allocates a new file's blocks before it is written, where the system allows. On ext4 a file
/// written without them, renamed over an existing one, is flushed toward the disk by the rename
/// itself (its guard for programs that replace files without fsync): for a 50 MB picture that
/// was 15-20 ms of the write, and more when the disk was busy. Best effort: if the blocks cannot
/// be had, the write itself reports why.
fn reserve_blocks(file: &std::fs::File, len: u64) {
    #[cfg(target_os = "linux")]
    if len > 0 {
        let _ = rustix::fs::fallocate(file, rustix::fs::FallocateFlags::empty(), 0, len);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (file, len);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_one() -> Image {
        Image {
            width: 2,
            height: 1,
            pixels: vec![[1, 2, 3], [4, 5, 6]],
        }
    }

    #[test]
    fn tga_has_the_course_header_and_bgr_pixels() {
        let bytes = encode(&two_by_one(), ImageFormat::Tga);
        assert_eq!(
            &bytes[..18],
            &[0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 1, 0, 24, 32]
        );
        assert_eq!(&bytes[18..], &[3, 2, 1, 6, 5, 4]);
    }

    #[test]
    fn ppm_is_binary_p6() {
        let bytes = encode(&two_by_one(), ImageFormat::Ppm);
        assert_eq!(bytes, b"P6\n2 1\n255\n\x01\x02\x03\x04\x05\x06");
    }

    #[test]
    fn png_decodes_to_the_same_pixels() {
        let bytes = encode(&two_by_one(), ImageFormat::Png);
        let decoded = image::load_from_memory(&bytes).unwrap().to_rgb8();
        assert_eq!(decoded.as_raw(), &[1, 2, 3, 4, 5, 6]);
    }

    #[test]
    fn formats_come_from_the_extension() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a/b.TGA")),
            Some(ImageFormat::Tga)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("b.png")),
            Some(ImageFormat::Png)
        );
        assert_eq!(ImageFormat::from_path(Path::new("b.jpg")), None);
        assert_eq!(ImageFormat::from_path(Path::new("ppm")), None);
    }
}
