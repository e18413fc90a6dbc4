//! A job's progress on the terminal: a bar drawn from its [`Progress`] while the job runs on
//! this thread. Nothing is drawn when stderr is not a terminal (a pipe, a test, a cluster log)
//! or for a job done within half a second.

use std::io::IsTerminal;
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use udc_core::Progress;

/// Steps of the bar: a tenth of a percent.
const STEPS: u64 = 1000;

/// Runs `job`, drawing `progress` as a bar labelled `label` when `show` and stderr is a
/// terminal.
pub fn with_bar<T>(progress: &Progress, show: bool, label: &str, job: impl FnOnce() -> T) -> T {
    if !show || !std::io::stderr().is_terminal() {
        return job();
    }
    let (done_tx, done_rx) = channel::<()>();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            // A quick job draws nothing.
            if done_rx.recv_timeout(Duration::from_millis(500)) != Err(RecvTimeoutError::Timeout) {
                return;
            }
            let bar = ProgressBar::with_draw_target(Some(STEPS), ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {msg} {wide_bar} {percent} % (ETA {eta})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar.set_message(label.to_string());
            while done_rx.recv_timeout(Duration::from_millis(200)) == Err(RecvTimeoutError::Timeout)
            {
                bar.set_position((f64::from(progress.fraction()) * STEPS as f64) as u64);
            }
            bar.finish_and_clear();
        });
        let out = job();
        drop(done_tx);
        out
    })
}
