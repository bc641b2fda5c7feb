//! Pictures to files: TGA in the course's exact layout, binary PPM, and PNG, by extension.
//!
//! TGA and PPM are written here (a header and the bytes: the course's TGA layout, top-left origin
//! and BGR, is not what a general encoder picks); PNG goes through the `png` crate. Each is
//! written row by row as the rows come ([`PictureWriter`]). Every file
//! is written to a temporary file beside its target and renamed into place only when all of a
//! run's files are complete, so a failed run leaves no partial image and touches no existing one.

use std::cell::RefCell;
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use crate::error::Error;
use crate::shade::Image;

/// A picture file's format, chosen by the extension of its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// Uncompressed 24-bit Targa in the course's layout: top-left origin, B, G, R bytes.
    Tga,
    /// Binary PPM (P6).
    Ppm,
    /// PNG (fast compression, each row filtered against the row above).
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
    let bytes = SharedBytes::default();
    PictureWriter::new(bytes.clone(), format, image.width, image.height)
        .and_then(|mut writer| {
            writer.write_rows(&image.pixels)?;
            writer.finish()
        })
        .expect("writing to memory cannot fail");
    bytes.0.take()
}

/// Bytes written to memory, still there when the writer that owned them is gone (the PNG
/// stream keeps its writer to the end).
#[derive(Clone, Default)]
struct SharedBytes(Rc<RefCell<Vec<u8>>>);

impl Write for SharedBytes {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A picture file written as its rows come, top to bottom: the header when made, then the rows
/// in any runs, each a whole number of rows; [`PictureWriter::finish`] after the last. A render
/// hands its rows on as its bands are finished, so a big picture need never be whole in memory.
pub struct PictureWriter<W: Write + 'static> {
    encoder: Encoder<W>,
}

enum Encoder<W: Write + 'static> {
    Tga { out: W, bgr: Vec<u8> },
    Ppm(W),
    // Boxed: the stream's state is ten times the others', and there is one writer a file.
    Png(Box<png::StreamWriter<'static, W>>),
}

/// Pixels turned into a TGA's B, G, R bytes at a time: a run of rows goes out in pieces of
/// this many pixels, so the copy stays small and in cache.
const TGA_PIECE: usize = 16 * 1024;

/// A PNG's compressed data goes out in chunks of up to this many bytes (the encoder's buffer:
/// a megabyte of it was a megabyte more of memory to clear, for nothing a reader notices).
const PNG_CHUNK: usize = 64 << 10;

impl<W: Write + 'static> PictureWriter<W> {
    /// Starts a `width` × `height` picture in `format`, writing its header to `out`. A TGA's
    /// sides must be at most [`TGA_MAX_SIDE`] (the command line sees to that).
    pub fn new(
        mut out: W,
        format: ImageFormat,
        width: u32,
        height: u32,
    ) -> std::io::Result<PictureWriter<W>> {
        let encoder = match format {
            ImageFormat::Tga => {
                // Uncompressed true colour (type 2), 24 bits, descriptor 32: rows top to bottom.
                let [w0, w1] = (width as u16).to_le_bytes();
                let [h0, h1] = (height as u16).to_le_bytes();
                out.write_all(&[0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, w0, w1, h0, h1, 24, 32])?;
                Encoder::Tga {
                    out,
                    bgr: Vec::new(),
                }
            }
            ImageFormat::Ppm => {
                write!(out, "P6\n{width} {height}\n255\n")?;
                Encoder::Ppm(out)
            }
            ImageFormat::Png => {
                let mut encoder = png::Encoder::new(out, width, height);
                encoder.set_color(png::ColorType::Rgb);
                encoder.set_depth(png::BitDepth::Eight);
                encoder.set_compression(png::Compression::Fast);
                // Up, not Adaptive (each of five filters tried on every row): a render's rows
                // are mostly runs of background or smooth shading, which Up suits; the bunny at
                // 4096² encodes in 17.6 ms instead of 30.0, its file 5.6 % larger.
                encoder.set_filter(png::Filter::Up);
                let writer = encoder.write_header()?;
                Encoder::Png(Box::new(writer.into_stream_writer_with_size(PNG_CHUNK)?))
            }
        };
        Ok(PictureWriter { encoder })
    }

    /// The next rows.
    pub fn write_rows(&mut self, pixels: &[[u8; 3]]) -> std::io::Result<()> {
        match &mut self.encoder {
            Encoder::Tga { out, bgr } => {
                for piece in pixels.chunks(TGA_PIECE) {
                    bgr.clear();
                    bgr.extend(piece.iter().flat_map(|&[r, g, b]| [b, g, r]));
                    out.write_all(bgr)?;
                }
                Ok(())
            }
            Encoder::Ppm(out) => out.write_all(pixels.as_flattened()),
            Encoder::Png(stream) => stream.write_all(pixels.as_flattened()),
        }
    }

    /// Ends the file (a PNG's last chunks) and flushes it.
    pub fn finish(self) -> std::io::Result<()> {
        match self.encoder {
            Encoder::Tga { mut out, .. } | Encoder::Ppm(mut out) => out.flush(),
            Encoder::Png(stream) => Ok(stream.finish()?),
        }
    }
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
    /// Each file's target, its temporary file, and the bytes reserved for it.
    files: Vec<(PathBuf, tempfile::NamedTempFile, u64)>,
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
            files.push((path.to_path_buf(), file, 0));
        }
        Ok(PendingOutputs { files })
    }

    /// Starts every file, in the order reserved: file i a picture of `shapes[i]`'s format and
    /// size (width, height). Each is written with [`OpenPicture::write_rows`] and ended with
    /// [`OpenPicture::finish`] before [`PendingOutputs::commit`].
    pub fn open(&mut self, shapes: &[(ImageFormat, u32, u32)]) -> Result<Vec<OpenPicture>, Error> {
        assert_eq!(self.files.len(), shapes.len(), "a shape for each file");
        self.files
            .iter_mut()
            .zip(shapes)
            .map(|((path, file, reserved), &(format, width, height))| {
                // Room for the raw pixels: a PNG takes less, and gives the rest back when
                // committed.
                *reserved = 3 * u64::from(width) * u64::from(height) + 64;
                reserve_blocks(file.as_file(), *reserved);
                // A second handle on the file, sharing its place in it: commit reads how far
                // the writer got.
                let writer = file
                    .as_file()
                    .try_clone()
                    .and_then(|file| {
                        PictureWriter::new(BufWriter::new(file), format, width, height)
                    })
                    .map_err(|e| write_error(path, e))?;
                Ok(OpenPicture {
                    path: path.clone(),
                    writer,
                })
            })
            .collect()
    }

    /// Renames every file into place, once all are written.
    ///
    /// No fsync: the rename already guarantees that the process, however it stops, leaves the
    /// old file or the new one, never a mix; only a crash of the whole machine could lose the
    /// new image, and syncing took longer than tracing a million rays.
    pub fn commit(self) -> Result<(), Error> {
        for (path, mut file, reserved) in self.files {
            let written = file.stream_position().map_err(|e| write_error(&path, e))?;
            if written < reserved {
                file.as_file()
                    .set_len(written)
                    .map_err(|e| write_error(&path, e))?;
            }
            file.persist(&path)
                .map_err(|e| write_error(&path, e.error))?;
        }
        Ok(())
    }
}

/// One output file being written: a [`PictureWriter`] whose errors name the file.
pub struct OpenPicture {
    path: PathBuf,
    writer: PictureWriter<BufWriter<std::fs::File>>,
}

impl OpenPicture {
    /// The next rows (see [`PictureWriter::write_rows`]).
    pub fn write_rows(&mut self, pixels: &[[u8; 3]]) -> Result<(), Error> {
        self.writer
            .write_rows(pixels)
            .map_err(|e| write_error(&self.path, e))
    }

    /// Ends the file.
    pub fn finish(self) -> Result<(), Error> {
        self.writer.finish().map_err(|e| write_error(&self.path, e))
    }
}

fn write_error(path: &Path, error: std::io::Error) -> Error {
    Error::Write {
        path: path.to_path_buf(),
        message: error.to_string(),
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
    fn a_picture_written_in_runs_of_rows_is_the_picture_written_whole() {
        let (width, height) = (37, 29);
        let pixels: Vec<[u8; 3]> = (0..width * height)
            .map(|i| [(i % 251) as u8, (i * 7 % 256) as u8, (i / 5 % 256) as u8])
            .collect();
        let image = Image {
            width,
            height,
            pixels,
        };
        for format in [ImageFormat::Tga, ImageFormat::Ppm, ImageFormat::Png] {
            let bytes = SharedBytes::default();
            let mut writer = PictureWriter::new(bytes.clone(), format, width, height).unwrap();
            // Runs of 1, 2, 3 ... rows, as bands of different sizes would come.
            let mut row = 0;
            for run in 1.. {
                if row == height {
                    break;
                }
                let rows = run.min(height - row);
                let at = (row * width) as usize;
                writer
                    .write_rows(&image.pixels[at..at + (rows * width) as usize])
                    .unwrap();
                row += rows;
            }
            writer.finish().unwrap();
            let streamed = bytes.0.take();
            let known = match format {
                ImageFormat::Tga => image::ImageFormat::Tga,
                ImageFormat::Ppm => image::ImageFormat::Pnm,
                ImageFormat::Png => image::ImageFormat::Png,
            };
            let decoded = image::load_from_memory_with_format(&streamed, known)
                .unwrap()
                .to_rgb8();
            assert_eq!(decoded.as_raw(), image.pixels.as_flattened(), "{format:?}");
            if format != ImageFormat::Png {
                assert_eq!(streamed, encode(&image, format), "{format:?}");
            }
        }
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
