//! One shape for every background computation and file task of the studio, so the UI thread
//! only draws: [`Job::spawn`] runs a closure on its own named thread with a [`Progress`] it can
//! report to and check for cancellation; the UI polls it once per frame; dropping the handle
//! cancels it. Results arrive as `Result<T, JobError>`, one level deep. Shapes built on it:
//! [`Keyed`], the job a view keeps for its newest key (its result comes back as a [`Finished`],
//! with the key and how long it ran); [`Answered`], a `Keyed` job and the newest answer it gave;
//! and [`Streaming`], a job whose parts arrive while it runs.
//!
//! The display workspace's live analysis is the one exception: [`super::Worker`] keeps a single
//! thread that coalesces a stream of designs (newest wins) rather than running one job.

use std::fmt;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, TryRecvError, channel};
use std::time::{Duration, Instant};

use super::notice::Notice;
use crate::core::{Progress, SimError};

/// Why a job gave no result.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JobError {
    /// The computation refused its input or failed; the message says what and where.
    Failed(String),
    /// It was cancelled (by the user, by a newer job, or by dropping its handle).
    Cancelled,
    /// Its thread ended without an answer (it could not start, or it panicked); the job's name.
    Stopped(&'static str),
}

impl fmt::Display for JobError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            JobError::Failed(m) => f.write_str(m),
            JobError::Cancelled => f.write_str("cancelled"),
            JobError::Stopped(name) => write!(f, "the {name} stopped unexpectedly"),
        }
    }
}

impl std::error::Error for JobError {}

impl From<SimError> for JobError {
    fn from(e: SimError) -> Self {
        match e {
            SimError::Cancelled => JobError::Cancelled,
            e => JobError::Failed(e.to_string()),
        }
    }
}

impl From<String> for JobError {
    fn from(e: String) -> Self {
        JobError::Failed(e)
    }
}

impl From<super::error::StudioError> for JobError {
    fn from(e: super::error::StudioError) -> Self {
        match e {
            super::error::StudioError::Sim(e) => e.into(),
            e => JobError::Failed(e.to_string()),
        }
    }
}

impl From<crate::io::IoError> for JobError {
    fn from(e: crate::io::IoError) -> Self {
        JobError::Failed(e.to_string())
    }
}

/// A value being produced on another thread.
pub struct Job<T> {
    rx: Receiver<Result<T, JobError>>,
    progress: Arc<Progress>,
    started: Instant,
    name: &'static str,
}

impl<T: Send + 'static> Job<T> {
    /// Runs `work` on a new thread named `name` (also the name errors use, e.g. "PSF job");
    /// `wake` is called when it is done, e.g. `request_repaint`.
    pub fn spawn<E: Into<JobError>>(
        name: &'static str,
        wake: impl Fn() + Send + 'static,
        work: impl FnOnce(&Progress) -> Result<T, E> + Send + 'static,
    ) -> Self {
        let (tx, rx) = channel();
        let progress = Arc::new(Progress::new());
        let p = progress.clone();
        // If the thread cannot start, `tx` is dropped with the closure and `poll` reports Stopped.
        let _ = std::thread::Builder::new()
            .name(name.replace(' ', "-"))
            .spawn(move || {
                let _ = tx.send(work(&p).map_err(Into::into));
                wake();
            });
        Job {
            rx,
            progress,
            started: Instant::now(),
            name,
        }
    }

    /// `Some(result)` once done; `None` while running.
    pub fn poll(&self) -> Option<Result<T, JobError>> {
        match self.rx.try_recv() {
            Ok(v) => Some(v),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(JobError::Stopped(self.name))),
        }
    }

    /// The fraction done, in `[0, 1]`, as the job last reported it.
    pub fn fraction(&self) -> f32 {
        self.progress.fraction()
    }

    /// Asks the job to stop at its next check; its result then arrives as `Cancelled`.
    pub fn cancel(&self) {
        self.progress.cancel();
    }

    /// Time since the job started.
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }
}

/// A [`Keyed`] job that ended: what it was started for, how it ended and how long it ran.
#[derive(Debug, PartialEq)]
pub struct Finished<K, T> {
    /// The key it was started for.
    pub key: K,
    /// Its value, or why there is none.
    pub result: Result<T, JobError>,
    /// How long it had run when its result was taken (the UI takes it within a frame of the
    /// end, and "computed in 2.3 s" reads this).
    pub elapsed: Duration,
}

/// The job a view keeps for one key (a design, a request): starting another replaces it, and
/// dropping the old handle cancels it, so the newest asked key wins. Its result comes back with
/// the key it was computed for.
pub struct Keyed<K, T> {
    slot: Option<(K, Job<T>)>,
}

impl<K, T> Default for Keyed<K, T> {
    fn default() -> Self {
        Keyed { slot: None }
    }
}

impl<K, T: Send + 'static> Keyed<K, T> {
    /// No job.
    pub const fn idle() -> Self {
        Keyed { slot: None }
    }

    /// Runs `job` for `key`, cancelling the one running before.
    pub fn start(&mut self, key: K, job: Job<T>) {
        self.slot = Some((key, job));
    }

    /// Whether a job is running.
    pub fn is_running(&self) -> bool {
        self.slot.is_some()
    }

    /// The key of the running job.
    pub fn key(&self) -> Option<&K> {
        self.slot.as_ref().map(|(k, _)| k)
    }

    /// The running job (for its progress and elapsed time).
    pub fn job(&self) -> Option<&Job<T>> {
        self.slot.as_ref().map(|(_, j)| j)
    }

    /// The running job and its key.
    pub fn current(&self) -> Option<(&K, &Job<T>)> {
        self.slot.as_ref().map(|(k, j)| (k, j))
    }

    /// Whether the running job is for a key `matches` accepts.
    pub fn is_running_for(&self, matches: impl FnOnce(&K) -> bool) -> bool {
        self.key().is_some_and(matches)
    }

    /// The finished job's key and result, once; `None` while it runs or when idle.
    pub fn poll(&mut self) -> Option<(K, Result<T, JobError>)> {
        self.finished().map(|f| (f.key, f.result))
    }

    /// The finished job, with how long it ran, once; `None` while it runs or when idle.
    pub fn finished(&mut self) -> Option<Finished<K, T>> {
        let result = self.slot.as_ref().and_then(|(_, j)| j.poll())?;
        self.slot.take().map(|(key, job)| Finished {
            key,
            result,
            elapsed: job.elapsed(),
        })
    }

    /// Cancels the running job, if any.
    pub fn stop(&mut self) {
        self.slot = None;
    }
}

/// A [`Keyed`] job and the newest answer it gave: the shape of a panel part that shows the
/// answer for its current key (the design, the options) and starts a job whenever the key
/// changes, the newest key winning. The last answer stays until a newer one arrives, so a view
/// can keep showing it, marked stale, while the next is computed.
pub struct Answered<K, T> {
    running: Keyed<K, T>,
    done: Option<(K, Result<T, JobError>)>,
}

impl<K, T> Default for Answered<K, T> {
    fn default() -> Self {
        Answered {
            running: Keyed::default(),
            done: None,
        }
    }
}

impl<K, T: Send + 'static> Answered<K, T> {
    /// Collects a finished job (a cancelled one, replaced by a newer key, keeps the last
    /// answer); then, unless the answer or the job in flight is for a key `is_now` accepts,
    /// starts `spawn(&key)` for `key()`. Returns whether an answer arrived this call.
    pub fn update(
        &mut self,
        is_now: impl Fn(&K) -> bool,
        key: impl FnOnce() -> K,
        spawn: impl FnOnce(&K) -> Job<T>,
    ) -> bool {
        let mut arrived = false;
        if let Some((k, result)) = self.running.poll()
            && !matches!(result, Err(JobError::Cancelled))
        {
            self.done = Some((k, result));
            arrived = true;
        }
        let answered = self.done.as_ref().is_some_and(|(k, _)| is_now(k));
        if !answered && !self.running.is_running_for(&is_now) {
            let key = key();
            let job = spawn(&key);
            self.running.start(key, job);
        }
        arrived
    }

    /// The newest answer and the key it is for (maybe an earlier one than the current).
    pub fn answer(&self) -> Option<(&K, &Result<T, JobError>)> {
        self.done.as_ref().map(|(k, r)| (k, r))
    }

    /// The answer, when it is for a key `is_now` accepts.
    pub fn answer_for(&self, is_now: impl FnOnce(&K) -> bool) -> Option<&Result<T, JobError>> {
        self.answer().filter(|(k, _)| is_now(k)).map(|(_, r)| r)
    }

    /// The job in flight, if any (for its progress).
    pub fn job(&self) -> Option<&Job<T>> {
        self.running.job()
    }

    /// Whether a job is in flight.
    pub fn is_running(&self) -> bool {
        self.running.is_running()
    }
}

/// A job whose results arrive part by part while it runs (a comparison's rows, each setup's
/// capture), with the key it was started for. Its work gets a [`Sender`] for the parts; the UI
/// takes the parts that [`Streaming::arrived`] each frame and the end once; dropping it cancels
/// the job.
pub struct Streaming<K, P> {
    key: K,
    job: Job<()>,
    parts: Receiver<P>,
}

impl<K, P: Send + 'static> Streaming<K, P> {
    /// Runs `work` on its own thread (as [`Job::spawn`]) for `key`; `work` sends each part as
    /// soon as it is ready.
    pub fn spawn<E: Into<JobError>>(
        name: &'static str,
        key: K,
        wake: impl Fn() + Send + 'static,
        work: impl FnOnce(&Progress, &Sender<P>) -> Result<(), E> + Send + 'static,
    ) -> Self {
        let (tx, parts) = channel();
        let job = Job::spawn(name, wake, move |p| work(p, &tx));
        Streaming { key, job, parts }
    }

    /// The key it was started for.
    pub fn key(&self) -> &K {
        &self.key
    }

    /// The job (for its progress and elapsed time).
    pub fn job(&self) -> &Job<()> {
        &self.job
    }

    /// The parts that arrived since the last call.
    pub fn arrived(&self) -> Vec<P> {
        self.parts.try_iter().collect()
    }

    /// How the job ended, once it has; `None` while it runs. The parts sent before the end are
    /// all in [`Streaming::arrived`] by then.
    pub fn ended(&self) -> Option<Result<(), JobError>> {
        self.job.poll()
    }

    /// Stops the job and returns its key and the parts that arrived last.
    pub fn stop(self) -> (K, Vec<P>) {
        self.job.cancel();
        let rest = self.arrived();
        (self.key, rest)
    }
}

impl<T> Drop for Job<T> {
    /// Nobody will read the result: stop the work instead of letting it burn the cores.
    fn drop(&mut self) {
        self.progress.cancel();
    }
}

/// File writes in flight, each answering with one line for the user ("saved …").
#[derive(Default)]
pub struct Writes(Vec<Job<String>>);

impl Writes {
    /// Writes on a helper thread; `write` answers with what was written.
    pub fn spawn<E: Into<JobError>>(
        &mut self,
        wake: impl Fn() + Send + 'static,
        write: impl FnOnce() -> Result<String, E> + Send + 'static,
    ) {
        self.0
            .push(Job::spawn("file write", wake, move |_| write()));
    }

    /// Whether none is in flight.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Takes the finished writes; the newest one's report, if any finished. A write that
    /// reports an empty line (an autosave) succeeds silently, leaving the user's last message.
    pub fn poll(&mut self) -> Option<Notice> {
        let mut last = None;
        self.0.retain(|job| match job.poll() {
            None => true,
            Some(Ok(line)) if line.is_empty() => false,
            Some(done) => {
                last = Some(match done {
                    Ok(line) => Notice::info(line),
                    Err(e) => Notice::error(e.to_string()),
                });
                false
            }
        });
        last
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait<T: Send + 'static>(job: &Job<T>) -> Result<T, JobError> {
        for _ in 0..2000 {
            if let Some(r) = job.poll() {
                return r;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        panic!("the job did not finish in 10 s");
    }

    #[test]
    fn result_and_errors_arrive_one_level_deep() {
        let ok = Job::spawn("test job", || {}, |_| Ok::<_, JobError>(41 + 1));
        assert_eq!(wait(&ok), Ok(42));
        let failed = Job::spawn("test job", || {}, |_| Err::<(), _>("bad size".to_string()));
        assert_eq!(wait(&failed), Err(JobError::Failed("bad size".into())));
        let sim = Job::spawn("test job", || {}, |_| Err::<(), _>(SimError::Cancelled));
        assert_eq!(wait(&sim), Err(JobError::Cancelled));
    }

    /// Asks `a` for `key` (a job computing `key × 10` when one starts) until it answers; the
    /// number of jobs started is added to `spawned`.
    fn answer_of(a: &mut Answered<u32, u32>, key: u32, spawned: &mut u32) -> bool {
        a.update(
            |k| *k == key,
            || key,
            |k| {
                *spawned += 1;
                let v = *k * 10;
                Job::spawn("test job", || {}, move |_| Ok::<_, JobError>(v))
            },
        )
    }

    fn settle(a: &mut Answered<u32, u32>, key: u32, spawned: &mut u32) {
        for _ in 0..2000 {
            if answer_of(a, key, spawned) && a.answer_for(|k| *k == key).is_some() {
                return;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        panic!("no answer in 10 s");
    }

    /// An answer is kept per key: the same key starts no second job, a new key starts one while
    /// the old answer stays readable (but not as the new key's), and a job cancelled by a newer
    /// key never becomes the answer.
    #[test]
    fn answered_keeps_the_last_answer_until_the_new_key_has_its_own() {
        let mut a: Answered<u32, u32> = Answered::default();
        let mut spawned = 0;
        settle(&mut a, 1, &mut spawned);
        assert_eq!(a.answer_for(|k| *k == 1), Some(&Ok(10)));
        assert!(!answer_of(&mut a, 1, &mut spawned), "answered: nothing new");
        assert_eq!(spawned, 1, "one job for one key");
        // Key 2: a job starts, and key 1's answer is still there (not as key 2's).
        answer_of(&mut a, 2, &mut spawned);
        assert_eq!(spawned, 2);
        assert!(a.answer().is_some());
        settle(&mut a, 2, &mut spawned);
        assert_eq!(a.answer(), Some((&2, &Ok(20))));
        assert_eq!(a.answer_for(|k| *k == 1), None);
        // A job that ends cancelled is asked again, not taken as the answer.
        let mut b: Answered<u32, u32> = Answered::default();
        b.update(
            |k| *k == 7,
            || 7,
            |_| {
                Job::spawn(
                    "test job",
                    || {},
                    |p: &Progress| {
                        while !p.is_cancelled() {
                            std::thread::sleep(Duration::from_millis(1));
                        }
                        Err::<u32, _>(JobError::Cancelled)
                    },
                )
            },
        );
        if let Some(job) = b.job() {
            job.cancel();
        }
        let mut again = 0;
        settle(&mut b, 7, &mut again);
        assert_eq!(b.answer(), Some((&7, &Ok(70))));
        assert_eq!(again, 1, "asked once more after the cancel");
    }

    /// A newer key replaces the job in flight and cancels it; the result comes back once, with
    /// the key it was computed for.
    #[test]
    fn the_newest_key_wins_and_the_old_job_is_cancelled() {
        let (tx, rx) = std::sync::mpsc::channel();
        let mut keyed: Keyed<u32, u32> = Keyed::idle();
        keyed.start(
            1,
            Job::spawn(
                "test job",
                || {},
                move |p: &Progress| {
                    while !p.is_cancelled() {
                        std::thread::sleep(Duration::from_millis(1));
                    }
                    let _ = tx.send("cancelled");
                    Err::<u32, _>(JobError::Cancelled)
                },
            ),
        );
        assert!(keyed.is_running_for(|k| *k == 1));
        keyed.start(2, Job::spawn("test job", || {}, |_| Ok::<_, JobError>(20)));
        assert_eq!(rx.recv_timeout(Duration::from_secs(10)), Ok("cancelled"));
        assert_eq!(keyed.key(), Some(&2));
        let mut got = None;
        for _ in 0..2000 {
            got = keyed.poll();
            if got.is_some() {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(got, Some((2, Ok(20))));
        assert!(!keyed.is_running());
        assert_eq!(keyed.poll(), None);
    }

    /// The time of a finished run stays readable after its handle is gone.
    #[test]
    fn a_finished_keyed_job_keeps_its_key_and_time() {
        let mut keyed: Keyed<&str, u8> = Keyed::idle();
        keyed.start(
            "v",
            Job::spawn(
                "test job",
                || {},
                |_| {
                    std::thread::sleep(Duration::from_millis(20));
                    Ok::<_, JobError>(7)
                },
            ),
        );
        let mut done = None;
        for _ in 0..2000 {
            done = keyed.finished();
            if done.is_some() {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let done = done.expect("the job finished");
        assert_eq!((done.key, done.result), ("v", Ok(7)));
        assert!(done.elapsed >= Duration::from_millis(20));
        assert!(keyed.finished().is_none());
    }

    #[test]
    fn a_panicking_job_reports_stopped_with_its_name() {
        let job = Job::spawn(
            "PSF job",
            || {},
            |_| -> Result<(), JobError> { panic!("boom") },
        );
        let e = wait(&job).expect_err("a panic gives no value");
        assert_eq!(e, JobError::Stopped("PSF job"));
        assert_eq!(e.to_string(), "the PSF job stopped unexpectedly");
    }

    #[test]
    fn cancel_and_drop_stop_a_running_job() {
        let (seen_tx, seen_rx) = channel();
        let job = Job::spawn(
            "test job",
            || {},
            move |p: &Progress| {
                while !p.is_cancelled() {
                    std::thread::sleep(Duration::from_millis(1));
                }
                let _ = seen_tx.send(());
                p.check()
            },
        );
        assert!(job.poll().is_none(), "still running");
        drop(job);
        assert!(
            seen_rx.recv_timeout(Duration::from_secs(10)).is_ok(),
            "dropping the handle cancels the work"
        );
        let job = Job::spawn(
            "test job",
            || {},
            |p: &Progress| {
                p.set(0.5);
                while !p.is_cancelled() {
                    std::thread::sleep(Duration::from_millis(1));
                }
                p.check()
            },
        );
        job.cancel();
        assert_eq!(wait(&job), Err(JobError::Cancelled));
        assert!((job.fraction() - 0.5).abs() < 1e-6);
    }

    /// Every part arrives, in order, before or right after the end; stopping cancels the work
    /// and hands back the key and what arrived last.
    #[test]
    fn a_streaming_job_delivers_every_part_and_stops_on_request() {
        let s: Streaming<&str, u32> = Streaming::spawn(
            "test job",
            "run",
            || {},
            |_, tx| {
                for i in 0..5 {
                    let _ = tx.send(i);
                }
                Ok::<_, JobError>(())
            },
        );
        let mut parts = Vec::new();
        let mut end = None;
        for _ in 0..2000 {
            parts.extend(s.arrived());
            end = s.ended();
            if end.is_some() {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        parts.extend(s.arrived());
        assert_eq!(end, Some(Ok(())));
        assert_eq!(parts, vec![0, 1, 2, 3, 4]);
        assert_eq!(*s.key(), "run");

        let (tx_done, rx_done) = std::sync::mpsc::channel();
        let (tx_sent, rx_sent) = std::sync::mpsc::channel();
        let endless: Streaming<u8, u8> = Streaming::spawn(
            "test job",
            7,
            || {},
            move |p, tx| {
                let _ = tx.send(1);
                let _ = tx_sent.send(());
                while !p.is_cancelled() {
                    std::thread::sleep(Duration::from_millis(1));
                }
                let _ = tx_done.send(());
                Err::<(), _>(JobError::Cancelled)
            },
        );
        assert_eq!(rx_sent.recv_timeout(Duration::from_secs(10)), Ok(()));
        let (key, rest) = endless.stop();
        assert_eq!(key, 7);
        assert_eq!(rest, vec![1]);
        assert_eq!(rx_done.recv_timeout(Duration::from_secs(10)), Ok(()));
    }
}
