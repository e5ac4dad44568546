//! Output folders made before a long computation and removed again when it
//! fails.

use crate::export::{check_folder_writable, ExportError};
use std::path::{Path, PathBuf};

/// A folder that cannot be made or written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{}: cannot create directory: {cause}", .path.display())]
    Create {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error(transparent)]
    Write(#[from] ExportError),
}

/// The folders [`OutputFolder::make`] made, deepest first; removed again
/// on drop, if still empty, unless kept.
pub struct OutputFolder {
    made: Vec<PathBuf>,
    keep: bool,
}

impl OutputFolder {
    /// Makes the output folder `dir` and checks that it takes files (the
    /// error names `first`, the first file the command writes there), so
    /// that a path that cannot be written fails before the computation.
    pub fn make(dir: &Path, first: &str) -> Result<Self, OutputError> {
        let folder = Self {
            made: dir
                .ancestors()
                .take_while(|d| !d.as_os_str().is_empty() && !d.exists())
                .map(Path::to_path_buf)
                .collect(),
            keep: false,
        };
        std::fs::create_dir_all(dir).map_err(|cause| OutputError::Create {
            path: dir.to_path_buf(),
            cause,
        })?;
        check_folder_writable(dir, first)?;
        Ok(folder)
    }

    /// Keeps the folders: the command succeeded.
    pub fn keep(mut self) {
        self.keep = true;
    }
}

impl Drop for OutputFolder {
    fn drop(&mut self) {
        if !self.keep {
            for dir in &self.made {
                // Fails, and keeps the folder, where files were written.
                let _ = std::fs::remove_dir(dir);
            }
        }
    }
}
