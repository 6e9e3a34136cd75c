//! Each dispatch's time inside real steps, from timestamp queries.
//!
//! Timing a stage alone ([`super::GpuSolver::time_stage`]) repeats it over
//! one state with nothing before or after it; inside a step the same
//! dispatch follows others, waits on their barriers and starts a new pass
//! after the reorder. Where the adapter has timestamp queries inside
//! compute passes, a timestamp after every dispatch of a batch of real
//! steps gives each dispatch's share of the step as it runs: the interval
//! between a timestamp and the one before is booked to the dispatch that
//! ends it (the first dispatch of a step carries the pass boundary, the
//! reorder's interval the reorder's passes and copies).

use serde::Serialize;

/// One dispatch's (or the reorder's) time inside the profiled steps.
#[derive(Debug, Clone, Serialize)]
pub struct DispatchTime {
    /// The shader it comes from (`neighbours`, `kinematics`, ...; `reorder`).
    pub stage: String,
    /// Its entry point, or its role where one entry point runs twice a
    /// step with other constants (the leapfrog's `energy` walk and
    /// `book_*` contact passes).
    pub kernel: String,
    pub calls_per_step: f64,
    pub seconds_per_step: f64,
}

/// Where a batch of real steps spent its device time.
#[derive(Debug, Clone, Serialize)]
pub struct StepProfile {
    pub steps: u32,
    /// From the first timestamp to the last, per step.
    pub seconds_per_step: f64,
    /// In the order a step first runs them.
    pub dispatches: Vec<DispatchTime>,
}

/// The timestamps of a batch being encoded: one at the start, then one
/// after each dispatch.
pub(super) struct StepTimer {
    pub set: wgpu::QuerySet,
    capacity: u32,
    /// `(stage, kernel)` of the interval that ends at each timestamp after
    /// the first.
    marks: Vec<(String, String)>,
}

impl StepTimer {
    /// A timer for at most `capacity` timestamps (the first included).
    pub fn new(dev: &wgpu::Device, capacity: u32) -> Self {
        let capacity = capacity.clamp(2, wgpu::QUERY_SET_MAX_QUERIES);
        let set = dev.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("step timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: capacity,
        });
        Self {
            set,
            capacity,
            marks: Vec::new(),
        }
    }

    /// Timestamps written so far.
    pub fn written(&self) -> u32 {
        self.marks.len() as u32 + 1
    }

    fn take(&mut self, stage: &str, kernel: &str) -> Option<u32> {
        let i = self.written();
        if i >= self.capacity {
            return None;
        }
        self.marks.push((stage.to_string(), kernel.to_string()));
        Some(i)
    }

    /// The first timestamp, before anything it times.
    pub fn start(&mut self, enc: &mut wgpu::CommandEncoder) {
        enc.write_timestamp(&self.set, 0);
    }

    pub fn after_pass_dispatch(
        &mut self,
        pass: &mut wgpu::ComputePass<'_>,
        stage: &str,
        kernel: &str,
    ) {
        if let Some(i) = self.take(stage, kernel) {
            pass.write_timestamp(&self.set, i);
        }
    }

    pub fn after_encoder_work(
        &mut self,
        enc: &mut wgpu::CommandEncoder,
        stage: &str,
        kernel: &str,
    ) {
        if let Some(i) = self.take(stage, kernel) {
            enc.write_timestamp(&self.set, i);
        }
    }

    /// The profile from the resolved ticks of the written timestamps
    /// (`period`: nanoseconds a tick).
    pub fn profile(&self, ticks: &[u64], period: f32, steps: u32) -> StepProfile {
        profile_of(&self.marks, ticks, period, steps)
    }
}

/// Each interval `ticks[k] → ticks[k + 1]` booked to `marks[k]`, summed by
/// mark and divided by the steps.
fn profile_of(marks: &[(String, String)], ticks: &[u64], period: f32, steps: u32) -> StepProfile {
    let steps = steps.max(1);
    let secs = |a: u64, b: u64| b.saturating_sub(a) as f64 * period as f64 * 1e-9;
    let mut rows: Vec<DispatchTime> = Vec::new();
    for (k, (stage, kernel)) in marks.iter().enumerate() {
        let dt = secs(ticks[k], ticks[k + 1]);
        match rows
            .iter_mut()
            .find(|r| &r.stage == stage && &r.kernel == kernel)
        {
            Some(r) => {
                r.calls_per_step += 1.0;
                r.seconds_per_step += dt;
            }
            None => rows.push(DispatchTime {
                stage: stage.clone(),
                kernel: kernel.clone(),
                calls_per_step: 1.0,
                seconds_per_step: dt,
            }),
        }
    }
    for r in &mut rows {
        r.calls_per_step /= steps as f64;
        r.seconds_per_step /= steps as f64;
    }
    StepProfile {
        steps,
        seconds_per_step: secs(ticks[0], ticks[marks.len()]) / steps as f64,
        dispatches: rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_go_to_the_dispatch_that_ends_them() {
        let marks = [
            ("neighbours", "a"),
            ("forces", "b"),
            ("neighbours", "a"),
            ("forces", "b"),
        ];
        let marks: Vec<(String, String)> = marks
            .iter()
            .map(|(s, k)| (s.to_string(), k.to_string()))
            .collect();
        let p = profile_of(&marks, &[100, 110, 140, 145, 185], 1000.0, 2);
        assert_eq!(p.steps, 2);
        assert!((p.seconds_per_step - 42.5e-6).abs() < 1e-12);
        assert_eq!(p.dispatches.len(), 2);
        assert_eq!(p.dispatches[0].kernel, "a");
        assert!((p.dispatches[0].calls_per_step - 1.0).abs() < 1e-12);
        assert!((p.dispatches[0].seconds_per_step - 7.5e-6).abs() < 1e-12);
        assert!((p.dispatches[1].seconds_per_step - 35e-6).abs() < 1e-12);
    }
}
