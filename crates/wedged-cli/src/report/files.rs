//! Output files written atomically: a temporary sibling of the destination, renamed into place,
//! so that a reader never sees a half-written file and an unwritable path fails before a long
//! run ([`JsonTarget`], [`PendingFile`]) or names itself after it ([`write_atomic`]).

use std::fmt;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// Where `--json` sends the JSON. A file target holds its temporary file, created in the
/// destination's directory before the run, and is renamed into place by [`JsonTarget::commit`].
#[derive(Debug)]
pub enum JsonTarget {
    Stdout,
    File { path: PathBuf, temp: NamedTempFile },
}

/// The JSON file could not be written; the message names it.
#[derive(Debug)]
pub struct WriteError(String);

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WriteError {}

impl JsonTarget {
    /// Whether `path` names stdout (`-`): for `--json`, `--jsonl` and `condense --mtx`.
    pub fn is_stdout(path: &Path) -> bool {
        path == Path::new("-")
    }

    /// `-` is stdout; anything else a file, whose temporary sibling is created now.
    pub fn open(path: &Path) -> Result<JsonTarget, WriteError> {
        if JsonTarget::is_stdout(path) {
            return Ok(JsonTarget::Stdout);
        }
        let fail = |e: io::Error| {
            WriteError(format!(
                "{}: cannot write the JSON file: {e}",
                path.display()
            ))
        };
        if path.is_dir() {
            return Err(WriteError(format!(
                "{}: is a directory, not a JSON file name",
                path.display()
            )));
        }
        let temp = temp_beside(path).map_err(fail)?;
        Ok(JsonTarget::File {
            path: path.to_path_buf(),
            temp,
        })
    }

    /// Writes `text` to the temporary file and renames it over the destination. Stdout targets
    /// are written by the caller.
    pub fn commit(self, text: &str) -> Result<(), WriteError> {
        self.commit_with(|out| out.write_all(text.as_bytes()))
    }

    /// As [`JsonTarget::commit`], the text written by `write` to a buffered writer on the
    /// temporary file (a document written as it is made, never held whole).
    pub fn commit_with(
        self,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), WriteError> {
        let JsonTarget::File { path, mut temp } = self else {
            return Ok(());
        };
        let fail = |e: io::Error| {
            WriteError(format!(
                "{}: cannot write the JSON file: {e}",
                path.display()
            ))
        };
        let mut out = io::BufWriter::new(&mut temp);
        write(&mut out).map_err(fail)?;
        out.flush().map_err(fail)?;
        drop(out);
        temp.as_file().sync_all().map_err(fail)?;
        temp.persist(&path).map_err(|e| fail(e.error))?;
        Ok(())
    }
}

/// A temporary file in `path`'s directory (so that renaming it over `path` is atomic), with the
/// permissions of an ordinary new file (0666 less the umask), not tempfile's 0600.
fn temp_beside(path: &Path) -> io::Result<NamedTempFile> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".wedged-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// The file of `--jsonl`: one line per piece, appended and flushed as each is found (from any
/// thread), so that it holds every piece found so far whatever stops the run. It is written in
/// place, not atomically: a reader may watch it grow. `-` is stdout (a pipe's reader gets each
/// piece as it is found). A write that fails is remembered and the rest are skipped;
/// [`JsonLines::finish`] reports it.
pub struct JsonLines {
    path: PathBuf,
    /// The writer (the file's, or stdout) and its first failure.
    state: std::sync::Mutex<(Box<dyn Write + Send>, Option<io::Error>)>,
    /// The file, to sync at the end; `None` for stdout.
    file: Option<std::fs::File>,
}

impl std::fmt::Debug for JsonLines {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "JsonLines({})", self.path.display())
    }
}

impl JsonLines {
    /// Creates (or truncates) the file now, before the run; `-` writes to stdout.
    pub fn create(path: &Path) -> Result<JsonLines, WriteError> {
        if JsonTarget::is_stdout(path) {
            return Ok(JsonLines {
                path: path.to_path_buf(),
                state: std::sync::Mutex::new((Box::new(io::stdout()), None)),
                file: None,
            });
        }
        if path.is_dir() {
            return Err(WriteError(format!(
                "{}: is a directory, not a file name for --jsonl",
                path.display()
            )));
        }
        let file = std::fs::File::create(path).map_err(|e| {
            WriteError(format!(
                "{}: cannot write the --jsonl file: {e}",
                path.display()
            ))
        })?;
        let sync = file.try_clone().map_err(|e| {
            WriteError(format!(
                "{}: cannot write the --jsonl file: {e}",
                path.display()
            ))
        })?;
        Ok(JsonLines {
            path: path.to_path_buf(),
            state: std::sync::Mutex::new((Box::new(io::BufWriter::new(file)), None)),
            file: Some(sync),
        })
    }

    /// Appends a pattern as one line ([`crate::report::json::pattern_line`]).
    pub fn write_pattern(&self, p: &wedged::Pattern) {
        self.write(&crate::report::json::pattern_line(p));
    }

    /// Appends `line` (which ends with a newline) and flushes it.
    pub fn write(&self, line: &str) {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let (writer, error) = &mut *state;
        if error.is_none() {
            if let Err(e) = writer
                .write_all(line.as_bytes())
                .and_then(|()| writer.flush())
            {
                *error = Some(e);
            }
        }
    }

    /// Flushes the file; the first failed write, if any, as an error naming the file.
    pub fn finish(self) -> Result<(), WriteError> {
        let (mut writer, error) = self.state.into_inner().unwrap_or_else(|e| e.into_inner());
        let fail = |e: io::Error| {
            WriteError(format!(
                "{}: cannot write the --jsonl file: {e}",
                self.path.display()
            ))
        };
        // A reader of stdout that stops reading (`| head`) is no failure, as for the summary.
        let closed = |e: &io::Error| self.file.is_none() && e.kind() == io::ErrorKind::BrokenPipe;
        if let Some(e) = error {
            return if closed(&e) { Ok(()) } else { Err(fail(e)) };
        }
        match writer.flush() {
            Err(e) if !closed(&e) => return Err(fail(e)),
            _ => {}
        }
        match &self.file {
            Some(file) => file.sync_all().map_err(fail),
            None => Ok(()),
        }
    }
}

/// A file written atomically after a run (`wedged sweep --svg`): its temporary sibling is created
/// before the run, so that an unwritable path fails before a long computation, and is renamed
/// into place by [`PendingFile::commit`] (or removed when dropped uncommitted).
#[derive(Debug)]
pub struct PendingFile {
    path: PathBuf,
    temp: NamedTempFile,
    what: &'static str,
}

impl PendingFile {
    /// `what` names the file in errors ("SVG file").
    pub fn open(path: &Path, what: &'static str) -> Result<PendingFile, WriteError> {
        not_stdout(path, what)?;
        if path.is_dir() {
            return Err(WriteError(format!(
                "{}: is a directory, not a file name for the {what}",
                path.display()
            )));
        }
        let temp = temp_beside(path)
            .map_err(|e| WriteError(format!("{}: cannot write the {what}: {e}", path.display())))?;
        Ok(PendingFile {
            path: path.to_path_buf(),
            temp,
            what,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `bytes` to the temporary file and renames it over the destination.
    pub fn commit(self, bytes: &[u8]) -> Result<(), WriteError> {
        let PendingFile {
            path,
            mut temp,
            what,
        } = self;
        let fail =
            |e: io::Error| WriteError(format!("{}: cannot write the {what}: {e}", path.display()));
        temp.write_all(bytes).map_err(fail)?;
        temp.as_file().sync_all().map_err(fail)?;
        temp.persist(&path).map_err(|e| fail(e.error))?;
        Ok(())
    }
}

/// Writes `bytes` to `path` through a temporary sibling renamed into place, so that a reader
/// never sees a half-written file. `what` names the file in errors ("VTU file").
pub fn write_atomic(path: &Path, bytes: &[u8], what: &str) -> Result<(), WriteError> {
    not_stdout(path, what)?;
    let fail =
        |e: io::Error| WriteError(format!("{}: cannot write the {what}: {e}", path.display()));
    let mut temp = temp_beside(path).map_err(fail)?;
    temp.write_all(bytes).map_err(fail)?;
    temp.as_file().sync_all().map_err(fail)?;
    temp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}

/// `-` names stdout for `--json`, `--jsonl` and `condense --mtx` only; another file given as
/// `-` is refused rather than written to a file of that name in the working directory.
fn not_stdout(path: &Path, what: &str) -> Result<(), WriteError> {
    if JsonTarget::is_stdout(path) {
        Err(WriteError(format!(
            "-: the {what} goes to a file, not to stdout: give its name"
        )))
    } else {
        Ok(())
    }
}

/// Creates the output directory of `option` (and its parents). `-` (stdout, for the file
/// options) and an existing file are refused.
pub fn create_output_dir(dir: &Path, option: &str) -> Result<(), String> {
    if JsonTarget::is_stdout(dir) {
        return Err(format!(
            "-: {option} needs a directory name (- is stdout for --json, --jsonl and condense \
             --mtx only)"
        ));
    }
    if dir.exists() && !dir.is_dir() {
        return Err(format!(
            "{}: {option} needs a directory, and this is a file",
            dir.display()
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        format!(
            "{}: cannot create the {option} directory: {e}",
            dir.display()
        )
    })
}
