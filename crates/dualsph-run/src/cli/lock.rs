//! One run at a time per output directory: `dualsph run` (and `--resume`) holds an exclusive
//! lock on `DIR/.lock` for its whole life, so a second run or resume into the same directory
//! is refused, naming the first one's process, instead of both writing its files.
//!
//! The exclusion is the operating system's file lock (`File::try_lock`), not the file's
//! existence: the lock is released when the process ends however it ends, so a lock file left
//! by a killed run does not block the next one. The file holds the holder's process id, for
//! the message. It is removed when the run ends; a process that opened it just before it
//! was removed checks that the path still names the file it locked, and opens again if not.

use super::exit::{self, Failure};
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The lock file's name in the output directory (what the emptiness checks ignore).
pub const LOCK_FILE: &str = ".lock";

/// The lock on an output directory, held until dropped: then the lock file is removed, and
/// the directory too when this lock made it and nothing else was written there.
pub(crate) struct OutDirLock {
    // dropped after `drop` below has removed the path: the lock is held until then
    _file: File,
    path: PathBuf,
    made_dir: Option<PathBuf>,
}

impl Drop for OutDirLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
        if let Some(dir) = &self.made_dir {
            // only an empty directory is removed
            let _ = std::fs::remove_dir(dir);
        }
    }
}

/// Takes the lock of the output directory `dir`, making the directory if it does not exist;
/// refuses (invalid input, exit status 2) when another process holds it.
pub(crate) fn lock_out_dir(dir: &Path) -> Result<OutDirLock, Failure> {
    let io = |e: std::io::Error| {
        Failure::new(exit::IO, format!("output directory {}: {e}", dir.display()))
    };
    let made_dir = (!dir.exists()).then(|| dir.to_path_buf());
    std::fs::create_dir_all(dir).map_err(io)?;
    let path = dir.join(LOCK_FILE);
    loop {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(in_use(dir, &mut file)),
            Err(TryLockError::Error(e)) => return Err(io(e)),
        }
        if !still_at(&file, &path) {
            // its holder removed it between our open and our lock: lock the new one
            continue;
        }
        file.set_len(0).map_err(io)?;
        write!(file, "{}", std::process::id()).map_err(io)?;
        return Ok(OutDirLock {
            _file: file,
            path,
            made_dir,
        });
    }
}

/// The refusal of a directory locked by another process, naming its process id when the
/// lock file holds one (only a number is read from it; nothing else of it is shown).
fn in_use(dir: &Path, file: &mut File) -> Failure {
    let mut text = String::new();
    let read = file
        .rewind()
        .and_then(|()| file.take(32).read_to_string(&mut text));
    let holder = match read.ok().and_then(|_| text.trim().parse::<u32>().ok()) {
        Some(pid) => format!("process {pid}"),
        None => "another process".to_string(),
    };
    Failure::new(
        exit::INVALID_INPUT,
        format!(
            "output directory {} is in use by another run or resume ({holder} holds {}); \
             wait for it to end, or choose another --out",
            dir.display(),
            dir.join(LOCK_FILE).display()
        ),
    )
}

/// Whether `path` still names the open `file` (not a file made after it was removed).
#[cfg(unix)]
fn still_at(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether `path` still names the open `file` (where files have no inode number to compare:
/// that it still exists).
#[cfg(not(unix))]
fn still_at(_file: &File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_is_refused_and_the_first_one_cleans_up() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let lock = lock_out_dir(&dir).unwrap();
        let pid = std::process::id().to_string();
        assert_eq!(std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap(), pid);
        // a second open file description of the same file conflicts, as another process's
        let e = lock_out_dir(&dir).err().unwrap();
        assert_eq!(e.code, exit::INVALID_INPUT);
        assert!(
            e.message.contains(&format!("process {pid}")),
            "{}",
            e.message
        );
        drop(lock);
        // the lock file and the directory the lock made are gone; a new lock is taken
        assert!(!dir.exists());
        let again = lock_out_dir(&dir).unwrap();
        std::fs::write(dir.join("run.json"), "{}").unwrap();
        drop(again);
        assert!(dir.join("run.json").exists() && !dir.join(LOCK_FILE).exists());
    }

    #[test]
    fn a_lock_file_left_by_a_dead_process_does_not_block() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join(LOCK_FILE), "4194303").unwrap();
        let lock = lock_out_dir(tmp.path()).unwrap();
        drop(lock);
        assert!(tmp.path().exists());
    }
}
