//! Atomic file replacement: write to a temporary file in the destination
//! directory, flush and fsync it, then rename it over the final name.
//!
//! After a crash the final name therefore refers either to the complete old
//! content or to the complete new content, never to a torn file. A stray
//! temporary file (`.<name>.XXXXXX.tmp`) may survive a hard crash; it is never
//! confused with a real output because of its name.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::OutputError;

/// Directory that holds `path` (`.` for a bare file name).
pub(crate) fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Atomically replace the file at `path` with `bytes`.
///
/// The data go to a temporary file in the same directory, which is flushed,
/// fsync'ed and then renamed onto `path` (replacing any existing file). The
/// directory itself is fsync'ed afterwards on a best-effort basis so the rename
/// is durable too. On error the previous content of `path` (if any) is left
/// untouched and the temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Atomically replace the file at `path` with whatever `f` writes.
///
/// `f` receives a buffered writer onto a temporary file in the same directory
/// as `path`; if it returns an error nothing is changed at `path`. Otherwise
/// the temporary file is flushed, fsync'ed and renamed onto `path`, exactly as
/// in [`write_atomic`].
pub fn write_atomic_with(
    path: &Path,
    f: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), OutputError> {
    let err = |op: &'static str| {
        let path = path.to_path_buf();
        move |source: io::Error| OutputError::Io { path, op, source }
    };
    let dir = parent_dir(path);
    let name = path
        .file_name()
        .ok_or_else(|| {
            err("determine file name of")(io::Error::new(
                io::ErrorKind::InvalidInput,
                "path has no file name",
            ))
        })?
        .to_string_lossy()
        .into_owned();

    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // Output files are ordinary data files: rw-r--r-- (subject to umask)
        // instead of tempfile's private default of rw-------.
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let mut tmp = builder
        .tempfile_in(&dir)
        .map_err(err("create temporary file for"))?;

    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        f(&mut w).map_err(err("write"))?;
        w.flush().map_err(err("flush"))?;
    }
    tmp.as_file().sync_all().map_err(err("fsync"))?;
    tmp.persist(path)
        .map_err(|e| err("rename temporary file onto")(e.error))?;
    sync_dir(&dir);
    Ok(())
}

/// Best-effort fsync of a directory so that a completed rename survives a
/// power loss. Some platforms/filesystems refuse to fsync directories; that is
/// ignored because the file content itself is already durable.
fn sync_dir(dir: &Path) {
    if cfg!(unix)
        && let Ok(d) = File::open(dir)
    {
        let _ = d.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn replaces_existing_file_and_leaves_no_temp_files() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("out.txt");
        std::fs::write(&path, b"old content that is longer").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        write_atomic_with(&path, |w| write!(w, "third {}", 3)).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "third 3");
        assert_eq!(names(tmp.path()), vec!["out.txt".to_string()]);
    }

    #[cfg(unix)]
    #[test]
    fn written_file_is_world_readable() {
        use std::os::unix::fs::PermissionsExt;
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("perm.txt");
        write_atomic(&path, b"x").unwrap();
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        // Readable like a file created the ordinary way (umask applies), not 0600.
        let plain = tmp.path().join("plain.txt");
        std::fs::write(&plain, b"x").unwrap();
        let plain_mode = std::fs::metadata(&plain).unwrap().permissions().mode();
        assert_eq!(mode & 0o744, plain_mode & 0o744);
    }

    #[test]
    fn failing_writer_keeps_old_content_and_no_temp_files() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("keep.txt");
        std::fs::write(&path, b"original").unwrap();
        let err = write_atomic_with(&path, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        })
        .unwrap_err();
        assert_eq!(err.path(), path);
        assert!(err.to_string().contains("keep.txt"), "{err}");
        assert_eq!(std::fs::read(&path).unwrap(), b"original");
        assert_eq!(names(tmp.path()), vec!["keep.txt".to_string()]);
    }

    #[test]
    fn parent_is_a_file_gives_error_naming_path() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("plain");
        std::fs::write(&file, b"").unwrap();
        let path = file.join("out.csv");
        let err = write_atomic(&path, b"x").unwrap_err();
        assert!(matches!(err, OutputError::Io { .. }));
        assert_eq!(err.path(), path);
        assert!(err.to_string().contains(&*path.to_string_lossy()), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn read_only_directory_gives_error_naming_path() {
        use std::os::unix::fs::PermissionsExt;
        let tmp = tempfile::tempdir().unwrap();
        let ro = tmp.path().join("ro");
        std::fs::create_dir(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        // Privileged users (root in containers) ignore directory permissions.
        let probe = ro.join("probe");
        let privileged = std::fs::write(&probe, b"").is_ok();
        if !privileged {
            let path = ro.join("out.csv");
            let err = write_atomic(&path, b"x").unwrap_err();
            assert_eq!(err.path(), path);
            assert!(err.to_string().contains("out.csv"), "{err}");
        }
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    }

    #[test]
    fn bare_file_name_uses_current_directory() {
        assert_eq!(parent_dir(Path::new("x.csv")), PathBuf::from("."));
        assert_eq!(parent_dir(Path::new("a/x.csv")), PathBuf::from("a"));
    }
}
