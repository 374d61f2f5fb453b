//! Progress of `gng3d simplify` on stderr (`job::Observer`): signals while GNG3D trains, then
//! the steps after training, counted and named as they run (GNG3D-Q spends most of a run
//! there); a spinner while QEM contracts; the cells done with `--partition auto`.

use gng3d_core::{PlannedStep, Progress, StepRecord};
use indicatif::{ProgressBar, ProgressStyle};

/// The bar of one run (hidden with `--json` or when stderr is not a terminal).
pub(crate) struct JobBar {
    json: bool,
    bar: Option<ProgressBar>,
    /// The steps after training, once known.
    plan: Vec<PlannedStep>,
    /// The next step's place in the plan.
    next: usize,
}

impl JobBar {
    /// No bar yet: it appears with the run's first report.
    pub(crate) fn new(json: bool) -> JobBar {
        JobBar {
            json,
            bar: None,
            plan: Vec::new(),
            next: 0,
        }
    }

    /// The step at `i` of the plan, as the bar names it.
    fn running(&self, i: usize) -> String {
        self.plan
            .get(i)
            .map_or_else(String::new, |s| match s.round {
                0 => s.step.to_string(),
                r => format!("{}, round {r}", s.step),
            })
    }

    /// Clear the bar.
    pub(crate) fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl job::Observer for JobBar {
    fn training(&mut self, p: &Progress, budget: u64) {
        let json = self.json;
        let bar = self.bar.get_or_insert_with(|| {
            crate::cli::progress::bar(
                budget,
                "{spinner} [{elapsed_precise}] {bar:20} {pos}/{len} signals {msg}",
                json,
            )
        });
        bar.set_position(p.signals.min(budget));
        bar.set_message(format!("{} nodes", p.nodes));
    }

    fn planned(&mut self, steps: &[PlannedStep]) {
        self.plan = steps.to_vec();
        self.next = 0;
        let first = self.running(0);
        let json = self.json;
        let bar = self
            .bar
            .get_or_insert_with(|| crate::cli::progress::bar(0, "", json));
        bar.set_length(steps.len() as u64);
        bar.set_position(0);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:20} {pos}/{len} steps after training, now: {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_message(first);
    }

    fn step(&mut self, record: &StepRecord) {
        // Steps left out (a time limit, a detail round that found nothing) report nothing: each
        // record moves the bar to its place in the plan.
        if let Some(j) = self
            .plan
            .get(self.next..)
            .unwrap_or(&[])
            .iter()
            .position(|s| s.step == record.step && s.round == record.round)
        {
            self.next += j + 1;
        }
        let message = self.running(self.next);
        if let Some(bar) = &self.bar {
            bar.set_position(self.next as u64);
            bar.set_message(message);
        }
    }

    fn cells(&mut self, done: usize, total: usize) {
        let json = self.json;
        let bar = self.bar.get_or_insert_with(|| {
            crate::cli::progress::bar(
                total as u64,
                "{spinner} [{elapsed_precise}] {bar:20} {pos}/{len} cells",
                json,
            )
        });
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    }

    fn contracting(&mut self) {
        let bar = crate::cli::progress::spinner(self.json);
        bar.set_message("QEM: contracting vertex pairs");
        self.bar = Some(bar);
    }
}
