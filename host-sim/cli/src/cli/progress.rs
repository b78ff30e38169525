//! A progress bar on stderr for the long commands (`run`, `hil`, `validate`).
//!
//! Why here and not in the library: the library reports progress through a plain
//! `FnMut(f64)` callback and stays free of terminal concerns; this wraps `indicatif` for the
//! command line. The bar appears only when stderr is a terminal (`std::io::IsTerminal`) and
//! the work has taken more than a second, so short runs, pipes, CI logs and tests see nothing
//! of it. Log lines ([`Progress::note`]) go to stderr either way, above the bar when it shows.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// How long work runs before its bar appears.
const DELAY: Duration = Duration::from_secs(1);
/// Units of a fraction bar ([`Progress::fraction`]).
const FRACTION_UNITS: u64 = 1000;

/// A bar over `len` units of work, shown once the work has taken longer than [`DELAY`].
pub struct Progress {
    bar: Option<ProgressBar>,
    /// `None`: never show a bar (stderr is not a terminal).
    target: Option<fn() -> ProgressDrawTarget>,
    template: &'static str,
    prefix: String,
    len: u64,
    position: u64,
    message: String,
    start: Instant,
    delay: Duration,
}

impl Progress {
    /// A bar over a fraction of one run (`run`, `hil`), fed by [`Progress::fraction`].
    pub fn run(what: &str) -> Self {
        Self::new(
            what,
            FRACTION_UNITS,
            "{prefix} [{bar:40}] {percent:>3} % {elapsed} (eta {eta})",
            terminal(),
        )
    }

    /// A bar over `len` steps (`validate`'s cases), fed by [`Progress::step`].
    pub fn steps(what: &str, len: u64) -> Self {
        Self::new(
            what,
            len,
            "{prefix} [{bar:40}] {pos}/{len} {elapsed} {msg}",
            terminal(),
        )
    }

    fn new(
        what: &str,
        len: u64,
        template: &'static str,
        target: Option<fn() -> ProgressDrawTarget>,
    ) -> Self {
        Progress {
            bar: None,
            target,
            template,
            prefix: format!("maglev: {what}"),
            len,
            position: 0,
            message: String::new(),
            start: Instant::now(),
            delay: DELAY,
        }
    }

    /// The library's progress callback: `f` of the run done.
    pub fn fraction(&mut self, f: f64) {
        let units = (f.clamp(0.0, 1.0) * self.len as f64).round() as u64;
        self.set(units);
    }

    /// Starts the next step: the previous one is done, `msg` names the new one. Also a log
    /// line on stderr (`maglev: {what}: {msg} …`).
    pub fn step(&mut self, msg: impl Into<String>) {
        if !self.message.is_empty() {
            self.position += 1;
        }
        self.message = msg.into();
        self.note(&format!("{}: {} …", self.prefix, self.message));
        let p = self.position;
        self.set(p);
    }

    /// A line on stderr, above the bar when it shows.
    pub fn note(&self, line: &str) {
        match &self.bar {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }

    fn set(&mut self, position: u64) {
        self.position = position.min(self.len);
        if self.bar.is_none() && self.start.elapsed() >= self.delay {
            if let Some(target) = self.target {
                let style = ProgressStyle::with_template(self.template)
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> ");
                let bar = ProgressBar::with_draw_target(Some(self.len), target())
                    .with_style(style)
                    .with_prefix(self.prefix.clone())
                    .with_elapsed(self.start.elapsed());
                bar.enable_steady_tick(Duration::from_millis(200));
                self.bar = Some(bar);
            }
        }
        if let Some(bar) = &self.bar {
            bar.set_position(self.position);
            bar.set_message(self.message.clone());
        }
    }
}

impl Drop for Progress {
    /// The bar leaves no trace: the command's own summary line follows.
    fn drop(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

/// stderr's draw target when stderr is a terminal.
fn terminal() -> Option<fn() -> ProgressDrawTarget> {
    std::io::stderr()
        .is_terminal()
        .then_some(ProgressDrawTarget::stderr as fn() -> ProgressDrawTarget)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_a_terminal_there_is_never_a_bar() {
        let mut p = Progress::new("run", 10, "{pos}", None);
        p.delay = Duration::ZERO;
        p.fraction(0.5);
        p.step("case");
        assert!(p.bar.is_none());
        assert_eq!(p.position, 5);
    }

    #[test]
    fn with_a_terminal_the_bar_appears_only_after_the_delay() {
        let mut p = Progress::new(
            "run",
            FRACTION_UNITS,
            "{pos}",
            Some(ProgressDrawTarget::hidden),
        );
        p.delay = Duration::from_secs(3600);
        p.fraction(0.25);
        assert!(p.bar.is_none(), "work under the delay shows nothing");
        p.delay = Duration::ZERO;
        p.fraction(0.5);
        let bar = p.bar.as_ref().expect("a bar after the delay");
        assert_eq!(bar.position(), 500);
        assert_eq!(bar.length(), Some(FRACTION_UNITS));
        p.fraction(2.0);
        assert_eq!(
            p.bar.as_ref().unwrap().position(),
            FRACTION_UNITS,
            "clamped"
        );
    }

    #[test]
    fn steps_count_the_cases_done() {
        let mut p = Progress::new("validate", 3, "{pos}", Some(ProgressDrawTarget::hidden));
        p.delay = Duration::ZERO;
        p.step("a");
        assert_eq!(p.position, 0, "the first case has only started");
        p.step("b");
        p.step("c");
        assert_eq!(p.bar.as_ref().unwrap().position(), 2);
        assert_eq!(p.bar.as_ref().unwrap().message(), "c");
    }
}
