//! What a run records as it goes: history rows interpolated at their
//! times, snapshots and checkpoints when they fall due, and the progress
//! display.

use super::*;

/// What both backends' loops record into: history rows at exact times,
/// snapshots at exact times, and the progress display.
///
/// A history row between two observed states is their linear
/// interpolation, so steps are never shortened for history. A snapshot
/// holds a whole state, which interpolation would not make a state of the
/// method (its boundary set and normals least of all), so the loops shorten
/// the step that would cross a snapshot time to land on it
/// ([`Recorder::next_stop`]): about one shortened step per snapshot.
pub(super) struct Recorder {
    pub(super) times: Vec<f64>,
    pub(super) next: usize,
    pub(super) prev: Option<(f64, Vec<f64>)>,
    pub(super) history: History,
    pub(super) snaps: Option<Snapshots>,
    pub(super) progress: Progress,
    pub(super) start: Instant,
    pub(super) end: f64,
    pub(super) particles: usize,
    pub(super) checkpoints: Option<Checkpoints>,
}

/// Where and when checkpoints go, and what each carries besides the
/// solver's and the recorder's state.
pub(super) struct Checkpoints {
    pub(super) dir: PathBuf,
    pub(super) every: f64,
    pub(super) next: f64,
    pub(super) scene: Scene,
    pub(super) scene_label: String,
    pub(super) backend: Backend,
    pub(super) adapter: Option<String>,
    /// The ledger as of the start of this process (its wall seconds those
    /// of the run before it); each checkpoint fills in the rest.
    pub(super) ledger: Ledger,
}

/// The snapshot times not yet written and the files written so far.
pub(super) struct Snapshots {
    pub(super) times: Vec<f64>,
    pub(super) next: usize,
    pub(super) series: SnapshotSeries,
}

/// Relative tolerance under which a state's time counts as a recorded
/// time: round-off of the time sum, far below any step.
pub(super) const AT_TIME: f64 = 1e-12;

impl Recorder {
    /// Observations `obs` of the state at time `t`: writes every history
    /// row up to `t`.
    pub(super) fn feed(&mut self, t: f64, obs: Vec<f64>) -> Result<(), RunError> {
        while self.next < self.times.len() && self.times[self.next] <= t * (1.0 + AT_TIME) {
            let tr = self.times[self.next];
            let row = match &self.prev {
                Some((tp, vp)) if tr < t => {
                    let a = (tr - tp) / (t - tp);
                    vp.iter().zip(&obs).map(|(p, c)| p + a * (c - p)).collect()
                }
                _ => obs.clone(),
            };
            self.history.push(tr, row)?;
            self.next += 1;
        }
        self.prev = Some((t, obs));
        Ok(())
    }

    pub(super) fn finished(&self) -> bool {
        self.next >= self.times.len()
    }

    /// A snapshot is due at the state at time `t`.
    pub(super) fn snapshot_due(&self, t: f64) -> bool {
        self.snaps.as_ref().is_some_and(|s| {
            s.times
                .get(s.next)
                .is_some_and(|&ts| ts <= t * (1.0 + AT_TIME))
        })
    }

    /// Where the coming steps must stop: the next snapshot time, else the end.
    pub(super) fn next_stop(&self) -> f64 {
        self.snaps
            .as_ref()
            .and_then(|s| s.times.get(s.next))
            .map_or(self.end, |&ts| ts.min(self.end))
    }

    /// Write the snapshot due at the state at `t` (labelled with its exact
    /// time, which `t` meets up to round-off). `prepared` is when the loop
    /// began making `fields` (the boundary set, the device readback), so
    /// that the snapshot's whole cost is booked.
    pub(super) fn snapshot(
        &mut self,
        t: f64,
        fields: &Fields,
        prepared: Instant,
    ) -> Result<(), RunError> {
        self.progress.out_of_range =
            Some(probe::count_out_of_range(fields.model, fields.state).total());
        let Some(s) = &mut self.snaps else {
            return Ok(());
        };
        let writing = Instant::now();
        s.series.seconds += (writing - prepared).as_secs_f64();
        while let Some(&ts) = s.times.get(s.next).filter(|&&ts| ts <= t * (1.0 + AT_TIME)) {
            s.series.write(ts, fields)?;
            s.next += 1;
        }
        self.progress.snapshots = Some(s.series.count());
        Ok(())
    }

    /// The time of the next checkpoint, if the run writes checkpoints.
    pub(super) fn next_checkpoint(&self) -> Option<f64> {
        self.checkpoints.as_ref().map(|c| c.next)
    }

    /// A checkpoint is due at the state at time `t` (never at the end: the
    /// run is complete there).
    pub(super) fn checkpoint_due(&self, t: f64) -> bool {
        self.checkpoints
            .as_ref()
            .is_some_and(|c| t >= c.next * (1.0 - AT_TIME) && !self.finished() && t < self.end)
    }

    /// Write the checkpoint of the state at `t`: the solver's part comes
    /// from the loop, with the stored penalty energy at the first state
    /// and the largest correction fallback so far.
    pub(super) fn checkpoint(
        &mut self,
        t: f64,
        stored0: f64,
        max_fallback: u32,
        solver: SolverState,
    ) -> Result<(), RunError> {
        let wall = self.start.elapsed().as_secs_f64();
        let Some(c) = &mut self.checkpoints else {
            return Ok(());
        };
        let next = next_multiple(t, c.every);
        let ck = Checkpoint {
            scene_label: c.scene_label.clone(),
            scene: c.scene.clone(),
            backend: c.backend,
            adapter: c.adapter.clone(),
            ledger: Ledger {
                stored0,
                max_fallback,
                wall_seconds: c.ledger.wall_seconds + wall,
                ..c.ledger.clone()
            },
            recorder: RecorderState {
                times: self.history.times.clone(),
                rows: self.history.rows.clone(),
                prev: self.prev.clone(),
                snapshots: self
                    .snaps
                    .as_ref()
                    .map_or(Vec::new(), |s| s.series.entries().to_vec()),
                checkpoint_every: c.every,
                next_checkpoint: next,
            },
            solver,
        };
        ck.write(&c.dir)?;
        c.next = next;
        Ok(())
    }

    /// Progress after `steps` steps, at simulated time `t`.
    pub(super) fn report(&mut self, t: f64, steps: u64) {
        let secs = self.start.elapsed().as_secs_f64().max(1e-9);
        let rate = steps as f64 * self.particles as f64 / secs;
        self.progress.update(t, self.end, steps, rate, secs);
    }
}

/// The first multiple of `every` after `t` (a `t` within round-off of a
/// multiple counts as on it).
pub(super) fn next_multiple(t: f64, every: f64) -> f64 {
    ((t / every * (1.0 + AT_TIME)).floor() + 1.0) * every
}

/// History times: `k · interval` from 0 through `end`, plus `end` itself if
/// the interval does not divide it.
pub fn history_times(end: f64, interval: f64) -> Vec<f64> {
    let n = (end / interval * (1.0 + 1e-12)).floor() as usize;
    let mut t: Vec<f64> = (0..=n).map(|k| k as f64 * interval).collect();
    if end - t[n] > 1e-9 * interval {
        t.push(end);
    }
    t
}

/// Plain progress lines come at least this often in simulated time (per
/// cent of the end time) and in wall time (seconds), whichever is first.
pub(super) const LINE_PERCENT: f64 = 5.0;

pub(super) const LINE_SECONDS: f64 = 10.0;

pub(super) struct Progress {
    pub(super) bar: Option<ProgressBar>,
    pub(super) plain: bool,
    /// Per cent of the end time at which the next plain line is due.
    pub(super) next_percent: f64,
    pub(super) last_line: Instant,
    /// Snapshots written so far, when the run writes snapshots.
    pub(super) snapshots: Option<usize>,
    /// Particles outside the solid range (`probe::out_of_range`) when last
    /// counted: every few steps on the CPU, at each snapshot on the GPU.
    pub(super) out_of_range: Option<usize>,
    /// Debris particles (docs/method.md, "Debris") at the last evaluation
    /// (the CPU path's count; the device keeps only its maximum).
    pub(super) debris: Option<usize>,
    /// Simulated time this process started from (that of the checkpoint
    /// when resuming): the wall time so far covers only what came after.
    pub(super) t0: f64,
}

/// The per cent of the end time at which the plain line after one at
/// `percent` is due: the next multiple of [`LINE_PERCENT`].
pub(super) fn next_line_percent(percent: f64) -> f64 {
    ((percent / LINE_PERCENT).floor() + 1.0) * LINE_PERCENT
}

/// Wall seconds left when this process has taken `elapsed` seconds to go
/// from simulated time `t0` to `t` of `end`, at the same pace; `None`
/// before any simulated time has passed.
pub(super) fn eta_seconds(elapsed: f64, t0: f64, t: f64, end: f64) -> Option<f64> {
    (t > t0).then(|| elapsed * (end - t).max(0.0) / (t - t0))
}

impl Progress {
    pub(super) fn new(opts: &RunOptions, t0: f64, end: f64) -> Self {
        let mut p = Self {
            bar: None,
            plain: false,
            // A resumed run's first plain line is due at the next multiple.
            next_percent: next_line_percent(100.0 * t0 / end),
            last_line: Instant::now(),
            snapshots: None,
            out_of_range: None,
            debris: None,
            t0,
        };
        // Quiet: the warnings and the closing line only.
        if opts.silent || opts.quiet {
            return p;
        }
        if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(1000);
            // The message takes what the terminal's width leaves and is cut
            // to it, so the line never wraps; it is there from the first frame.
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:20} {wide_msg} [{elapsed_precise} < {eta_precise}]",
                )
                .expect("a valid template"),
            );
            bar.set_message(bar_message(t0, end, 0, None, ""));
            // A resumed run's bar starts where the checkpoint was, and its
            // rate estimate from there (not from a jump at the first step).
            bar.set_position(((t0 / end).clamp(0.0, 1.0) * 1000.0) as u64);
            bar.reset_eta();
            p.bar = Some(bar);
        } else {
            p.plain = true;
        }
        p
    }

    /// `elapsed`: wall seconds since the run started.
    pub(super) fn update(&mut self, t: f64, end: f64, steps: u64, rate: f64, elapsed: f64) {
        let frac = (t / end).clamp(0.0, 1.0);
        let mut tail = self
            .snapshots
            .map_or(String::new(), |k| format!(", snapshots written: {k}"));
        if let Some(k) = self.out_of_range.filter(|&k| k > 0) {
            tail += &format!(", {k} particle(s) outside the solid range");
        }
        if let Some(k) = self.debris.filter(|&k| k > 0) {
            tail += &format!(", {k} debris");
        }
        if let Some(bar) = &self.bar {
            bar.set_position((frac * 1000.0) as u64);
            bar.set_message(bar_message(t, end, steps, Some(rate), &tail));
        } else if self.plain {
            let percent = frac * 100.0;
            let quiet_for = self.last_line.elapsed().as_secs_f64();
            if percent < self.next_percent && quiet_for < LINE_SECONDS {
                return;
            }
            self.next_percent = next_line_percent(percent);
            self.last_line = Instant::now();
            let eta = eta_seconds(elapsed, self.t0, t, end).map_or("unknown".into(), duration);
            eprintln!(
                "t = {t:.4e} s ({percent:.0} %), {}, {rate:.3e} particle-steps/s, ETA {eta}{tail}",
                steps_text(steps)
            );
        }
    }

    pub(super) fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// `1 step`, `2 steps`.
pub(super) fn steps_text(steps: u64) -> String {
    if steps == 1 {
        "1 step".to_string()
    } else {
        format!("{steps} steps")
    }
}

/// The progress bar's message: the simulated time against the end, the
/// steps and, once one is measured, the rate.
pub(super) fn bar_message(t: f64, end: f64, steps: u64, rate: Option<f64>, tail: &str) -> String {
    let rate = rate.map_or(String::new(), |r| format!(", {r:.3e} particle-steps/s"));
    format!(
        "t = {t:.3e} / {end:.3e} s, {}{rate}{tail}",
        steps_text(steps)
    )
}

/// How often the CPU loop counts the particles outside the solid range
/// for the progress line (a pass over the state, cheap against a step).
pub(super) const OUT_OF_RANGE_STEPS: u64 = 64;

/// A wall-clock duration for people: `42 s`, `3 min 07 s`, `2 h 05 min`.
pub(super) fn duration(secs: f64) -> String {
    let s = secs.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The time left is the pace of this process over what is left: a
    /// fresh run 40 % through after 8 s has 12 s to go; a run resumed at
    /// 50 % that reached 75 % in 10 s has 10 s to go (not the 3.3 s that
    /// the fraction since t = 0 would give).
    #[test]
    pub(super) fn eta_counts_from_where_the_process_started() {
        let close = |a: Option<f64>, b: f64| (a.expect("known") - b).abs() < 1e-12;
        assert!(close(eta_seconds(8.0, 0.0, 4e-6, 1e-5), 12.0));
        assert!(close(eta_seconds(10.0, 5e-6, 7.5e-6, 1e-5), 10.0));
        assert!(close(eta_seconds(3.0, 0.0, 1e-5, 1e-5), 0.0));
        assert_eq!(eta_seconds(1.0, 5e-6, 5e-6, 1e-5), None);
    }

    /// The bar's message from the first frame (no rate yet), one step in
    /// the singular, and the rate once measured.
    #[test]
    fn bar_message_from_the_first_frame() {
        assert_eq!(
            bar_message(0.0, 4e-6, 0, None, ""),
            "t = 0.000e0 / 4.000e-6 s, 0 steps"
        );
        assert_eq!(
            bar_message(1e-8, 4e-6, 1, Some(2.5e6), ", 3 debris"),
            "t = 1.000e-8 / 4.000e-6 s, 1 step, 2.500e6 particle-steps/s, 3 debris"
        );
    }

    /// Plain lines come at the multiples of LINE_PERCENT: a fresh run's
    /// first at 5 %, one resumed at 83 % next at 85 %, and after a line at
    /// exactly 85 % the next at 90 %.
    #[test]
    pub(super) fn plain_lines_at_the_next_multiple() {
        assert_eq!(next_line_percent(0.0), LINE_PERCENT);
        assert_eq!(next_line_percent(83.3), 85.0);
        assert_eq!(next_line_percent(85.0), 90.0);
    }
}
