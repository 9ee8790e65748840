//! An observer on a thread of its own: the bench hands it each tick's view as a copy and steps
//! on while the observer works through the ticks before (the waveform writer, whose text is as
//! costly as the environment models, on the second core).
//!
//! [`Threaded`] copies every call of the bench ([`Observer::begin`], `tick`, `finish`, the
//! period boundaries and replays) into a batch of [`BATCH`] calls and sends full batches through a
//! bounded queue of [`IN_FLIGHT`] batches to the thread, which makes the same calls, in the
//! same order, on the observer it owns. So the observer sees exactly what it would see on the
//! bench's thread and writes the same bytes. The queue is the back-pressure: when the thread
//! falls behind by [`IN_FLIGHT`] batches the bench waits. [`Observer::can_replay`] is a
//! question: the calls before it are sent and the bench waits for the thread's answer (the
//! bench asks only where it could skip whole periods). The observer's
//! [`Observer::needs_every_tick`] and [`Observer::replays_periods`] are read once, when the
//! thread starts.
//!
//! Errors: the first error of the observer ends its thread; the bench gets it at its next
//! sending of a batch, at the latest at `finish` (the ticks between are not written: the run
//! fails). A panic of the thread becomes an error that says so.

use crate::sim::{EnvSample, Observer, SimError, TickView};
use pmu50_core::{Inputs, Internals, Outputs, Regs};
use std::cell::RefCell;
use std::collections::VecDeque;
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

/// Calls per batch sent to the thread.
pub const BATCH: usize = 1024;
/// Batches on their way to the thread before the bench waits for it (about 1 MB of copies; 32
/// measured slower: the copies then leave the caches).
pub const IN_FLIGHT: usize = 4;

/// A copy of one [`TickView`].
#[derive(Clone, Copy)]
struct Record {
    tick: u64,
    time_ns: u64,
    regs: Regs,
    after: Regs,
    ports: Outputs,
    inputs: Inputs,
    internals: Internals,
    env: EnvSample,
}

impl Record {
    #[inline(always)]
    fn of(v: &TickView<'_>) -> Record {
        Record {
            tick: v.tick,
            time_ns: v.time_ns,
            regs: *v.regs,
            after: *v.after,
            ports: *v.ports,
            inputs: *v.inputs,
            internals: *v.internals,
            env: *v.env,
        }
    }

    #[inline(always)]
    fn view(&self) -> TickView<'_> {
        TickView {
            tick: self.tick,
            time_ns: self.time_ns,
            regs: &self.regs,
            after: &self.after,
            ports: &self.ports,
            inputs: &self.inputs,
            internals: &self.internals,
            env: &self.env,
        }
    }
}

/// One call of the bench, for the thread to make.
enum Call {
    Begin(Record),
    Tick(Record),
    Finish(Record),
    Boundary(u64),
    Moving(u64),
    /// [`Observer::can_replay`]: the answer goes back at once.
    CanReplay(u64, u64),
    Replay(u64, u64, u64),
}

/// The bounded queue of batches between the bench and the thread, with the emptied batches
/// coming back for reuse. Either side waits on a condition variable, without spinning: the
/// side that waits has nothing else to do, and the other needs the core.
struct Queue {
    state: Mutex<QueueState>,
    /// a batch was sent, or the bench closed the queue
    sent: Condvar,
    /// a batch was taken, or the thread ended
    taken: Condvar,
}

#[derive(Default)]
struct QueueState {
    full: VecDeque<Vec<Call>>,
    spare: Vec<Vec<Call>>,
    /// the bench sends no more
    closed: bool,
    /// the thread takes no more
    ended: bool,
}

impl Queue {
    fn lock(&self) -> MutexGuard<'_, QueueState> {
        // a panic while holding the lock cannot leave the state inconsistent (plain pushes and pops)
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Send `batch`, waiting while [`IN_FLIGHT`] are on their way; returns an emptied batch to
    /// fill next, or `None` when the thread has ended.
    fn send(&self, batch: Vec<Call>) -> Option<Vec<Call>> {
        let mut q = self.lock();
        while q.full.len() >= IN_FLIGHT && !q.ended {
            q = self.taken.wait(q).unwrap_or_else(|p| p.into_inner());
        }
        if q.ended {
            return None;
        }
        q.full.push_back(batch);
        let next = q.spare.pop();
        drop(q);
        self.sent.notify_one();
        Some(next.unwrap_or_else(|| Vec::with_capacity(BATCH)))
    }

    /// The bench sends no more.
    fn close(&self) {
        self.lock().closed = true;
        self.sent.notify_one();
    }

    /// The next batch, after giving back the emptied `done`; `None` once the bench has closed
    /// the queue and every batch is taken.
    fn take(&self, done: Option<Vec<Call>>) -> Option<Vec<Call>> {
        let mut q = self.lock();
        if let Some(d) = done {
            q.spare.push(d);
        }
        loop {
            if let Some(b) = q.full.pop_front() {
                drop(q);
                self.taken.notify_one();
                return Some(b);
            }
            if q.closed {
                return None;
            }
            q = self.sent.wait(q).unwrap_or_else(|p| p.into_inner());
        }
    }

    /// The thread takes no more (it ended, with or without an error).
    fn end(&self) {
        let mut q = self.lock();
        q.ended = true;
        q.full.clear();
        drop(q);
        self.taken.notify_one();
    }
}

/// Ends the queue when the thread ends, however it ends (a panic too), so that the bench never
/// waits for a thread that is gone.
struct EndOnDrop(Arc<Queue>);

impl Drop for EndOnDrop {
    fn drop(&mut self) {
        self.0.end();
    }
}

/// What the thread gives back when it ends: the observer after its last call, or the first
/// error.
type Outcome<O> = Result<O, SimError>;

/// The bench's end of the thread.
struct Link<O> {
    batch: Vec<Call>,
    queue: Arc<Queue>,
    answer: Receiver<bool>,
    worker: Option<JoinHandle<Outcome<O>>>,
    /// an error of the thread noticed where it could not be returned (`can_replay`)
    failed: Option<SimError>,
    what: String,
}

/// An observer `O` on a thread of its own (see the module documentation).
pub struct Threaded<O> {
    link: RefCell<Link<O>>,
    every_tick: bool,
    replays: bool,
    /// the observer back from its thread after `finish`
    done: Option<O>,
}

impl<O: Observer + Send + 'static> Threaded<O> {
    /// Start a thread for `o`; `what` names it in errors (the file it writes). When no thread
    /// can be started, `o` comes back.
    pub fn spawn(o: O, what: &str) -> Result<Threaded<O>, O> {
        let (every_tick, replays) = (o.needs_every_tick(), o.replays_periods());
        let queue = Arc::new(Queue {
            state: Mutex::new(QueueState::default()),
            sent: Condvar::new(),
            taken: Condvar::new(),
        });
        let theirs_q = Arc::clone(&queue);
        let (answer_to, answer) = mpsc::sync_channel(1);
        // The observer goes to the thread through a slot it can be taken back from when the
        // thread cannot start.
        let slot = Arc::new(Mutex::new(Some(o)));
        let theirs = Arc::clone(&slot);
        let started = std::thread::Builder::new()
            .name("pmu50-wave".into())
            .spawn(move || {
                let _end = EndOnDrop(Arc::clone(&theirs_q));
                let o = theirs
                    .lock()
                    .map_err(|_| SimError::observer("writer thread", "its observer was lost"))?
                    .take();
                let o =
                    o.ok_or_else(|| SimError::observer("writer thread", "its observer was lost"))?;
                work(o, &theirs_q, answer_to)
            });
        match started {
            Ok(worker) => Ok(Threaded {
                link: RefCell::new(Link {
                    batch: Vec::with_capacity(BATCH),
                    queue,
                    answer,
                    worker: Some(worker),
                    failed: None,
                    what: what.to_string(),
                }),
                every_tick,
                replays,
                done: None,
            }),
            Err(_) => {
                let o = slot.lock().ok().and_then(|mut s| s.take());
                // the thread never ran, so the observer is still in its slot
                Err(o.expect("an observer whose thread did not start is still in its slot"))
            }
        }
    }

    /// The observer, after `finish` (its thread has ended).
    pub fn into_inner(mut self) -> Option<O> {
        self.done.take()
    }

    #[inline(always)]
    fn push(&mut self, c: Call) -> Result<(), SimError> {
        let l = self.link.get_mut();
        l.batch.push(c);
        if l.batch.len() >= BATCH {
            l.send()?;
        }
        Ok(())
    }
}

impl<O> Link<O> {
    /// Send the batch to the thread (a reused one takes its place).
    fn send(&mut self) -> Result<(), SimError> {
        if let Some(e) = self.failed.take() {
            return Err(e);
        }
        if self.worker.is_none() {
            return Err(SimError::observer(
                self.what.clone(),
                "the writer thread has already ended",
            ));
        }
        let full = std::mem::take(&mut self.batch);
        match self.queue.send(full) {
            Some(next) => {
                self.batch = next;
                Ok(())
            }
            // the thread ended early: with its error
            None => Err(self.end().err().unwrap_or_else(|| {
                SimError::observer(self.what.clone(), "the writer thread ended before the run")
            })),
        }
    }

    /// Close the channel and wait for the thread.
    fn end(&mut self) -> Outcome<O> {
        self.queue.close();
        match self.worker.take() {
            None => Err(SimError::observer(
                self.what.clone(),
                "the writer thread has already ended",
            )),
            Some(w) => match w.join() {
                Ok(r) => r,
                Err(p) => {
                    let why = p
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| p.downcast_ref::<String>().cloned())
                        .unwrap_or_default();
                    Err(SimError::observer(
                        self.what.clone(),
                        format!("the writer thread panicked: {why}"),
                    ))
                }
            },
        }
    }
}

impl<O> Drop for Threaded<O> {
    /// A run that ends early (another observer's error) still waits for the thread, so that its
    /// temporary files are removed before the process ends.
    fn drop(&mut self) {
        let l = self.link.get_mut();
        l.queue.close();
        if let Some(w) = l.worker.take() {
            let _ = w.join();
        }
    }
}

/// The thread: every call of every batch on `o`, in order.
fn work<O: Observer>(mut o: O, queue: &Queue, answer: SyncSender<bool>) -> Outcome<O> {
    let mut done = None;
    while let Some(mut batch) = queue.take(done.take()) {
        for c in batch.drain(..) {
            match c {
                Call::Tick(r) => o.tick(&r.view())?,
                Call::Begin(r) => o.begin(&r.view())?,
                Call::Finish(r) => o.finish(&r.view())?,
                Call::Boundary(k) => o.period_boundary(k)?,
                Call::Moving(k) => o.moving_boundary(k)?,
                Call::CanReplay(k, len) => {
                    // the bench waits for the answer
                    let _ = answer.send(o.can_replay(k, len));
                }
                Call::Replay(k, periods, len) => o.replay(k, periods, len)?,
            }
        }
        done = Some(batch);
    }
    Ok(o)
}

impl<O: Observer + Send + 'static> Observer for Threaded<O> {
    fn begin(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.push(Call::Begin(Record::of(v)))
    }

    #[inline]
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.push(Call::Tick(Record::of(v)))
    }

    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        let l = self.link.get_mut();
        l.batch.push(Call::Finish(Record::of(v)));
        l.send()?;
        self.done = Some(l.end()?);
        Ok(())
    }

    fn needs_every_tick(&self) -> bool {
        self.every_tick
    }

    fn replays_periods(&self) -> bool {
        self.replays
    }

    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.push(Call::Boundary(k))
    }

    fn moving_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.push(Call::Moving(k))
    }

    fn can_replay(&self, k: u64, len: u64) -> bool {
        let mut l = self.link.borrow_mut();
        l.batch.push(Call::CanReplay(k, len));
        match l.send() {
            // no answer: the thread ended (its error comes with the next call)
            Ok(()) => l.answer.recv().unwrap_or(false),
            Err(e) => {
                l.failed = Some(e);
                false
            }
        }
    }

    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        self.push(Call::Replay(k, periods, len))
    }
}
