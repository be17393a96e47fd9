//! Reading the files a user names (scenes, and the meshes, outlines and particle files a
//! scene names) without letting the file decide how much is read: only a regular file
//! (not a device, pipe or directory, which could block or never end) and only up to a size
//! limit, checked before reading and again while reading (a file may grow, or report no
//! size at all, as those under `/proc` do).

use std::io::{self, Read};
use std::path::Path;

/// The largest scene file read: 16 MiB (scenes are a few kilobytes).
pub const SCENE_FILE_LIMIT: u64 = 16 << 20;

/// The largest mesh, outline or particle file a scene may name: 2 GiB (a particle CSV of
/// some ten million particles).
pub const INPUT_FILE_LIMIT: u64 = 2 << 30;

fn refuse(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// `n` bytes in the largest binary unit that keeps it whole or above 1 (`16 MiB`).
fn bytes(n: u64) -> String {
    match n {
        n if n >= 1 << 30 => format!("{} GiB", n as f64 / f64::from(1u32 << 30)),
        n if n >= 1 << 20 => format!("{} MiB", n as f64 / f64::from(1u32 << 20)),
        n => format!("{n} bytes"),
    }
}

/// Opens `path` for reading if it is a regular file (after following links) of at most
/// `limit` bytes; else an error of kind `InvalidInput` saying which.
pub fn open_input(path: &Path, limit: u64) -> io::Result<std::fs::File> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a directory"
        } else {
            "not a regular file (a device, pipe or socket)"
        };
        return Err(refuse(format!("it is {what}")));
    }
    if meta.len() > limit {
        return Err(refuse(format!(
            "it holds {} bytes, more than the {} read from such a file",
            meta.len(),
            bytes(limit)
        )));
    }
    std::fs::File::open(path)
}

/// The bytes of `path` ([`open_input`]), stopping with an error past `limit`.
pub fn read_input(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    let file = open_input(path, limit)?;
    let mut out = Vec::new();
    file.take(limit + 1).read_to_end(&mut out)?;
    if out.len() as u64 > limit {
        return Err(refuse(format!(
            "it grew past {} while being read",
            bytes(limit)
        )));
    }
    Ok(out)
}

/// The text of `path` ([`read_input`]); a file that is not UTF-8 is an error that says so
/// (without quoting it).
pub fn read_input_text(path: &Path, limit: u64) -> io::Result<String> {
    String::from_utf8(read_input(path, limit)?).map_err(|e| {
        refuse(format!(
            "it is not valid UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// A reader of `path` ([`open_input`]) that fails once more than `limit` bytes came.
pub fn bounded_reader(path: &Path, limit: u64) -> io::Result<impl Read> {
    Ok(Bounded {
        inner: open_input(path, limit)?,
        left: limit,
    })
}

struct Bounded<R> {
    inner: R,
    left: u64,
}

impl<R: Read> Read for Bounded<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.left = self
            .left
            .checked_sub(n as u64)
            .ok_or_else(|| refuse("it grew past its size limit while being read".into()))?;
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let small = dir.path().join("a.txt");
        std::fs::write(&small, "hello").unwrap();
        assert_eq!(read_input_text(&small, 5).unwrap(), "hello");
        let e = read_input_text(&small, 4).unwrap_err();
        assert!(e.to_string().contains("more than the 4 bytes"), "{e}");
        let e = read_input(dir.path(), 100).unwrap_err();
        assert!(e.to_string().contains("directory"), "{e}");
        let dev = Path::new("/dev/zero");
        if dev.exists() {
            let e = read_input(dev, 100).unwrap_err();
            assert!(e.to_string().contains("not a regular file"), "{e}");
        }
        // a sparse file is refused by its size before a byte is read
        let sparse = dir.path().join("sparse");
        std::fs::File::create(&sparse)
            .unwrap()
            .set_len(1 << 40)
            .unwrap();
        let e = read_input(&sparse, INPUT_FILE_LIMIT).unwrap_err();
        assert!(e.to_string().contains("more than the 2 GiB"), "{e}");
        std::fs::write(&small, [0xff, 0xfe]).unwrap();
        let e = read_input_text(&small, 5).unwrap_err();
        assert!(e.to_string().contains("not valid UTF-8"), "{e}");
    }

    #[test]
    fn a_bounded_reader_stops_a_file_past_its_limit() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("a");
        std::fs::write(&f, "0123456789").unwrap();
        let mut s = String::new();
        bounded_reader(&f, 10)
            .unwrap()
            .read_to_string(&mut s)
            .unwrap();
        assert_eq!(s, "0123456789");
        let mut r = Bounded {
            inner: &b"0123456789"[..],
            left: 4,
        };
        assert!(r.read_to_end(&mut Vec::new()).is_err());
    }
}
