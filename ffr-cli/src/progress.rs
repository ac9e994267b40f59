//! Progress of a batch of runs on standard error: a bar on a terminal, a
//! line per run otherwise, or nothing.

use std::io::IsTerminal;

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// A progress bar if stderr is a terminal, else one line per run.
    Auto,
    /// One line per run on stderr.
    Lines,
    /// Nothing.
    Silent,
}

/// The display of one batch of `total` runs.
pub struct Reporter {
    bar: Option<indicatif::ProgressBar>,
    lines: bool,
}

impl Reporter {
    /// A display for `total` runs, shown as `mode` says.
    pub fn new(mode: Progress, total: usize) -> Self {
        let tty = std::io::stderr().is_terminal();
        let bar = (mode == Progress::Auto && tty).then(|| {
            let bar = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {pos}/{len} {msg}",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar
        });
        let lines = mode == Progress::Lines || (mode == Progress::Auto && !tty);
        Self { bar, lines }
    }

    /// A run starts: `what` names it beside the bar.
    pub fn start(&self, what: impl Into<String>) {
        if let Some(b) = &self.bar {
            b.set_message(what.into());
        }
    }

    /// A run ended with the one-line summary `line`; `failed` runs are
    /// printed above the bar too.
    pub fn done(&self, line: &str, failed: bool) {
        if let Some(b) = &self.bar {
            if failed {
                b.println(line);
            }
            b.inc(1);
        } else if self.lines {
            eprintln!("{line}");
        }
    }

    /// The batch ended: clear the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
