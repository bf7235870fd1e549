//! `upload` and `download`: an object's contents (a DOMAIN, typically) into or from a file, with a
//! progress bar; Ctrl-C aborts the transfer on the bus.

use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use super::{emit, file_error};
use crate::{Tool, ToolError, UsageError};

/// `upload`'s arguments.
#[derive(Debug, clap::Args)]
pub struct UploadArgs {
    /// Node-ID, 1–127.
    pub node: u8,
    /// The object.
    pub object: String,
    /// Where the bytes go.
    pub file: PathBuf,
}

/// `download`'s arguments.
#[derive(Debug, clap::Args)]
pub struct DownloadArgs {
    /// Node-ID, 1–127.
    pub node: u8,
    /// The object.
    pub object: String,
    /// The bytes to send.
    pub file: PathBuf,
}

/// Ctrl-C aborts the transfer on the bus (0x08000000) instead of leaving the node in it.
pub fn cancel_on_interrupt(tool: &mut Tool) {
    let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let f = std::sync::Arc::clone(&flag);
    if ctrlc::set_handler(move || f.store(true, std::sync::atomic::Ordering::Relaxed)).is_ok() {
        tool.cancel = Some(flag);
    }
}

/// `upload`: the object's bytes into the file, and the rate; an interrupted upload's partial file
/// is removed.
pub fn upload(
    args: &UploadArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let UploadArgs { node, object, file } = args;
    let mut f = std::fs::File::create(file).map_err(|e| file_error(file, e))?;
    let bar = progress_bar(None);
    let started = Instant::now();
    let n = match tool.upload(*node, object, &mut f, |done, total| {
        if let Some(t) = total {
            bar.set_length(t);
        }
        bar.set_position(done);
    }) {
        Ok(n) => n,
        Err(ToolError::Interrupted { .. }) => {
            bar.finish_and_clear();
            drop(f);
            let _ = std::fs::remove_file(file);
            return Err(ToolError::Interrupted {
                removed: Some(file.clone()),
            });
        }
        Err(e) => return Err(e),
    };
    bar.finish_and_clear();
    let took = started.elapsed();
    emit(
        out,
        json,
        rate(n, took),
        serde_json::json!({"bytes": n, "seconds": took.as_secs_f64()}),
    )
}

/// `download`: the file's bytes into the object, and the rate.
pub fn download(
    args: &DownloadArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let DownloadArgs { node, object, file } = args;
    // Looked at before opening: opening a FIFO waits for a writer; a device has no length.
    let kind = std::fs::metadata(file).map_err(|e| file_error(file, e))?;
    if !kind.is_file() {
        return Err(UsageError::NotRegularFile { path: file.clone() }.into());
    }
    let mut f = std::fs::File::open(file).map_err(|e| file_error(file, e))?;
    let len = f.metadata().map_err(|e| file_error(file, e))?.len();
    let bar = progress_bar(Some(len));
    let started = Instant::now();
    tool.download(*node, object, &mut f, len, |done, _| bar.set_position(done))?;
    bar.finish_and_clear();
    let took = started.elapsed();
    emit(
        out,
        json,
        rate(len, took),
        serde_json::json!({"bytes": len, "seconds": took.as_secs_f64()}),
    )
}

/// A progress bar on standard error (hidden when it is not a terminal).
fn progress_bar(len: Option<u64>) -> indicatif::ProgressBar {
    let bar =
        indicatif::ProgressBar::with_draw_target(len, indicatif::ProgressDrawTarget::stderr());
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{bar:40} {bytes}/{total_bytes} {binary_bytes_per_sec} {eta}",
    ) {
        bar.set_style(style);
    }
    bar
}

/// "1048576 bytes in 0.52 s (1969.2 KiB/s)".
fn rate(bytes: u64, took: Duration) -> String {
    let secs = took.as_secs_f64().max(1e-6);
    format!(
        "{bytes} bytes in {secs:.2} s ({:.1} KiB/s)",
        bytes as f64 / 1024.0 / secs
    )
}
