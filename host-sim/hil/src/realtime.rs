//! Real-time pacing of a HIL run (`maglev hil --realtime`): each host step is a control
//! period of the wall clock, as on a bench where the plant runs against a real board.
//!
//! [`Paced`] wraps the run's [`Link`]. Period k (host step k, counting from 0) is released at
//! `t0 + k·T` (T = the step Δt, `t0` = the first `Step`): its first `Step` waits for that
//! instant, and its deadline is the next release, `t0 + (k+1)·T`, by which the `Commit` reply
//! must be back (every Newton iteration's `Step` and the plant's work in between included).
//! The schedule is absolute: a late period does not shift the ones after it, so a link too
//! slow for the rate shows as missed deadlines, never as silently stretched time.
//!
//! **Too slow** ([`TOO_SLOW`]): after a warm-up of [`WARMUP`] periods (the first exchanges,
//! caches, the port), more than [`MAX_MISS_FRACTION`] of the periods missing their deadline.
//! Judged after each period once [`WINDOW`] periods follow the warm-up (so a slow link stops
//! the run early) and at the end of the run; the run then fails with
//! [`Error::Invalid`] on `--realtime`, naming the rate, what was achieved and the exchange
//! latency (so the link's share of a period can be told from the plant's and the scheduler's).
//!
//! The clock is a [`Clock`], so the bookkeeping is tested with an injected one.

use crate::link::{Link, LinkStats};
use maglev_firmware_sim::protocol::{Request, Response};
use maglev_sim::{Error, Result};
use std::time::{Duration, Instant};

/// Periods at the start that are never judged.
pub const WARMUP: u64 = 20;
/// Judged periods (after the warm-up) before a run may be stopped early.
pub const WINDOW: u64 = 100;
/// The largest fraction of judged periods that may miss their deadline.
pub const MAX_MISS_FRACTION: f64 = 0.1;
/// The rule, as the error message and docs/hil.md state it.
pub const TOO_SLOW: &str = "more than 10 % of the periods after a 20-period warm-up missed \
                            their deadline";

/// Time since an origin, and sleeping until a given time.
pub trait Clock {
    fn now(&self) -> Duration;
    fn sleep_until(&mut self, t: Duration);
}

/// The wall clock (`Instant`; `thread::sleep`, so a period may start a scheduler slice late).
pub struct WallClock(Instant);

impl Default for WallClock {
    fn default() -> Self {
        WallClock(Instant::now())
    }
}

impl Clock for WallClock {
    fn now(&self) -> Duration {
        self.0.elapsed()
    }
    fn sleep_until(&mut self, t: Duration) {
        let left = t.saturating_sub(self.now());
        if !left.is_zero() {
            std::thread::sleep(left);
        }
    }
}

/// The pacing figures of a run (summary.json `realtime`; seconds).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RealtimeStats {
    /// The pace asked for: 1/T.
    pub rate_hz: f64,
    pub period_s: f64,
    /// Periods (host steps) run.
    pub periods: u64,
    /// Periods whose `Commit` reply came after the next release.
    pub deadline_misses: u64,
    /// The same among the periods after the warm-up (the ones the rule judges).
    pub judged_periods: u64,
    pub judged_misses: u64,
    /// How far past its deadline the latest-finishing period's `Commit` reply came (s; 0
    /// when none missed).
    pub worst_lateness_s: f64,
    /// Periods per second actually achieved: periods / (last commit − first release).
    pub achieved_hz: f64,
    /// Exchange latency (one request to its reply, retransmissions included): median, worst,
    /// and jitter = its standard deviation (population).
    pub latency_median_s: f64,
    pub latency_worst_s: f64,
    pub latency_jitter_s: f64,
}

/// A [`Link`] paced to a clock, one host step per period.
pub struct Paced<'a, C: Clock> {
    inner: &'a mut dyn Link,
    clock: C,
    period: Duration,
    /// The first release, and the step number and index of the period in progress.
    origin: Option<Duration>,
    current: Option<(u32, u64)>,
    last_done: Duration,
    latencies: Vec<f64>,
    periods: u64,
    misses: u64,
    judged_misses: u64,
    worst_late: Duration,
}

impl<'a, C: Clock> Paced<'a, C> {
    pub fn new(inner: &'a mut dyn Link, period_s: f64, clock: C) -> Self {
        Paced {
            inner,
            clock,
            period: Duration::from_secs_f64(period_s),
            origin: None,
            current: None,
            last_done: Duration::ZERO,
            latencies: Vec::new(),
            periods: 0,
            misses: 0,
            judged_misses: 0,
            worst_late: Duration::ZERO,
        }
    }

    /// The figures so far.
    pub fn stats(&self) -> RealtimeStats {
        let period_s = self.period.as_secs_f64();
        let mut sorted = self.latencies.clone();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median = match n {
            0 => 0.0,
            _ if n % 2 == 1 => sorted[n / 2],
            _ => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
        };
        let mean = sorted.iter().sum::<f64>() / n.max(1) as f64;
        let var = sorted.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / n.max(1) as f64;
        let span = self
            .last_done
            .saturating_sub(self.origin.unwrap_or_default());
        RealtimeStats {
            rate_hz: 1.0 / period_s,
            period_s,
            periods: self.periods,
            deadline_misses: self.misses,
            judged_periods: self.periods.saturating_sub(WARMUP),
            judged_misses: self.judged_misses,
            worst_lateness_s: self.worst_late.as_secs_f64(),
            achieved_hz: self.periods as f64 / span.as_secs_f64().max(1e-12),
            latency_median_s: median,
            latency_worst_s: sorted.last().copied().unwrap_or(0.0),
            latency_jitter_s: var.sqrt(),
        }
    }

    /// The end of the run: the figures, or the too-slow error ([`TOO_SLOW`]).
    pub fn finish(&self) -> Result<RealtimeStats> {
        let s = self.stats();
        if s.judged_misses as f64 > MAX_MISS_FRACTION * s.judged_periods as f64 {
            return Err(Error::invalid(
                "--realtime",
                format!(
                    "{:.0} Hz not kept: {} of {} periods after the warm-up finished past their \
                     deadline, the latest by {:.3} ms ({TOO_SLOW}); exchange latency median \
                     {:.3} ms, worst {:.3} ms (the rest of a period is the plant's work and the \
                     scheduler's); mean pace {:.0} periods/s (a period is late when it overruns \
                     its own deadline, whatever the mean)",
                    s.rate_hz,
                    s.judged_misses,
                    s.judged_periods,
                    1e3 * s.worst_lateness_s,
                    1e3 * s.latency_median_s,
                    1e3 * s.latency_worst_s,
                    s.achieved_hz,
                ),
            ));
        }
        Ok(s)
    }

    /// Waits for the release of the period of `step` if it is a new one.
    fn release(&mut self, step: u32) {
        if self.current.is_some_and(|(s, _)| s == step) {
            return;
        }
        let origin = *self.origin.get_or_insert_with(|| self.clock.now());
        let k = self.current.map_or(0, |(_, k)| k + 1);
        self.current = Some((step, k));
        self.clock.sleep_until(origin + self.period * k as u32);
    }

    /// Books the end of the period in progress (its `Commit` reply is in).
    fn complete(&mut self) -> Result<()> {
        let (Some(origin), Some((_, k))) = (self.origin, self.current) else {
            return Ok(());
        };
        self.last_done = self.clock.now();
        self.periods += 1;
        let deadline = origin + self.period * (k as u32 + 1);
        if self.last_done > deadline {
            self.worst_late = self.worst_late.max(self.last_done - deadline);
            self.misses += 1;
            if k >= WARMUP {
                self.judged_misses += 1;
            }
        }
        if self.periods >= WARMUP + WINDOW {
            self.finish()?;
        }
        Ok(())
    }
}

impl<C: Clock> Link for Paced<'_, C> {
    fn call(&mut self, req: Request) -> Result<Response> {
        let commit = match req {
            Request::Step { step, .. } | Request::StepAccel { step, .. } => {
                self.release(step);
                false
            }
            Request::Commit { .. } => true,
            Request::Config(_) | Request::Ping => return self.inner.call(req),
        };
        let t = self.clock.now();
        let reply = self.inner.call(req)?;
        self.latencies.push((self.clock.now() - t).as_secs_f64());
        if commit {
            self.complete()?;
        }
        Ok(reply)
    }
    fn stats(&self) -> LinkStats {
        self.inner.stats()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;
    use std::rc::Rc;

    /// A clock that moves only when told: by the fake link's latency, or by a sleep.
    #[derive(Clone, Default)]
    struct FakeClock {
        now: Rc<Cell<Duration>>,
        sleeps: Rc<Cell<u32>>,
    }

    impl Clock for FakeClock {
        fn now(&self) -> Duration {
            self.now.get()
        }
        fn sleep_until(&mut self, t: Duration) {
            if t > self.now.get() {
                self.sleeps.set(self.sleeps.get() + 1);
                self.now.set(t);
            }
        }
    }

    /// A firmware that answers the n-th request after `latency(n)` µs of the fake clock.
    struct FakeLink {
        clock: FakeClock,
        latency: fn(u64) -> u64,
        n: u64,
    }

    impl Link for FakeLink {
        fn call(&mut self, req: Request) -> Result<Response> {
            let us = (self.latency)(self.n);
            self.n += 1;
            self.clock
                .now
                .set(self.clock.now.get() + Duration::from_micros(us));
            Ok(match req {
                Request::Commit { step } => Response::Committed { step },
                _ => Response::Pong,
            })
        }
        fn stats(&self) -> LinkStats {
            LinkStats::default()
        }
    }

    /// Runs `periods` host steps of 1 ms, each three `Step`s (Newton iterations) and a
    /// `Commit`; the fake plant takes no time. Stops at the first error.
    fn drive(latency: fn(u64) -> u64, periods: u32) -> (Result<RealtimeStats>, FakeClock) {
        let clock = FakeClock::default();
        let mut link = FakeLink {
            clock: clock.clone(),
            latency,
            n: 0,
        };
        let mut paced = Paced::new(&mut link, 1e-3, clock.clone());
        let step = |step| Request::Step {
            step,
            codes: Default::default(),
        };
        let run = (|| {
            for s in 1..=periods {
                for _ in 0..3 {
                    paced.call(step(s))?;
                }
                paced.call(Request::Commit { step: s })?;
            }
            paced.finish()
        })();
        (run, clock)
    }

    #[test]
    fn a_fast_link_is_paced_to_the_period_and_misses_nothing() {
        // 4 × 100 µs per period: each period after the first sleeps until its release.
        let (s, clock) = drive(|_| 100, 50);
        let s = s.unwrap();
        assert_eq!(clock.sleeps.get(), 49);
        // The last period starts at 49 ms and ends 0.4 ms later.
        assert_eq!(clock.now.get(), Duration::from_micros(49_400));
        assert_eq!(
            (s.periods, s.deadline_misses, s.judged_periods),
            (50, 0, 30)
        );
        assert_eq!(s.latency_median_s, 100e-6);
        assert_eq!(s.latency_worst_s, 100e-6);
        // Zero, but for the rounding of the mean of 200 equal doubles (≈ 1e-19 s).
        assert!(s.latency_jitter_s < 1e-15, "{}", s.latency_jitter_s);
        assert!((s.achieved_hz - 50.0 / 49.4e-3).abs() < 1e-9);
    }

    /// Every 10th period has its `Commit` take 800 µs: 3 × 100 + 800 = 1.1 ms, one period
    /// late, and the next period starts 0.1 ms late but ends in time (0.4 ms of work).
    fn one_slow_commit_in_ten(n: u64) -> u64 {
        if n % 40 == 39 {
            800
        } else {
            100
        }
    }

    #[test]
    fn misses_and_latency_statistics_are_counted_by_the_definition() {
        let (s, _) = drive(one_slow_commit_in_ten, 60);
        let s = s.unwrap();
        // Periods 9, 19, …, 59: 6 misses, 4 of them after the 20-period warm-up.
        assert_eq!((s.periods, s.deadline_misses), (60, 6));
        assert_eq!((s.judged_periods, s.judged_misses), (40, 4));
        // 240 exchanges: 234 of 100 µs and 6 of 800 µs (what the fake link was told).
        let lat: Vec<f64> = (0..240)
            .map(|n| one_slow_commit_in_ten(n) as f64 * 1e-6)
            .collect();
        let mean = lat.iter().sum::<f64>() / 240.0;
        let sd = (lat.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / 240.0).sqrt();
        assert_eq!(s.latency_median_s, 100e-6);
        assert_eq!(s.latency_worst_s, 800e-6);
        // The closed form: 6/240 of the exchanges 700 µs above the rest, p = 0.025.
        let p: f64 = 6.0 / 240.0;
        let closed = 700e-6 * (p * (1.0 - p)).sqrt();
        assert!(
            (s.latency_jitter_s - sd).abs() < 1e-15,
            "{} {sd}",
            s.latency_jitter_s
        );
        assert!((s.latency_jitter_s - closed).abs() < 1e-12);
        // 10 % of the judged periods missed: allowed (more than 10 % is too slow).
        assert_eq!(
            s.judged_misses as f64,
            MAX_MISS_FRACTION * s.judged_periods as f64
        );
    }

    #[test]
    fn a_link_too_slow_for_the_rate_stops_the_run_after_the_window() {
        // 4 × 500 µs = 2 ms per 1 ms period: every period misses; the periods run back to
        // back, so the link achieves exactly 500 periods/s.
        let (r, clock) = drive(|_| 500, 1000);
        let msg = r.unwrap_err().to_string();
        assert_eq!(
            clock.now.get(),
            Duration::from_millis(2 * (WARMUP + WINDOW))
        );
        assert!(
            msg.starts_with("--realtime: 1000 Hz not kept: 100 of 100 periods after the warm-up"),
            "{msg}"
        );
        assert!(msg.contains("mean pace 500 periods/s"), "{msg}");
        // Period k ends at 2(k + 1) ms against its deadline (k + 1) ms: the last judged one,
        // k = 119, by 120 ms.
        assert!(
            msg.contains("finished past their deadline, the latest by 120.000 ms"),
            "{msg}"
        );
        assert!(msg.contains("median 0.500 ms, worst 0.500 ms"), "{msg}");
        assert!(!msg.contains('\n'));
        // A short run that ends before the window is judged at its end.
        let (r, _) = drive(|_| 500, 30);
        assert!(r.unwrap_err().to_string().contains("10 of 10 periods"));
    }
}
