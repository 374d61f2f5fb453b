//! [`GngRun`]: GNG3D's run on one model, for the job and for a front end that steps the training
//! itself (the viewer's live network): the request's options resolved once against the mesh,
//! the trainer built, and the run after training ([`GngRun::finish`], the output's attributes
//! taken from the original's surface there) giving the job's [`Outcome`].

use crate::{JobError, Method, Observer, Outcome, Request};
use gng3d_core::{GngOptions, GngParams, StepRecord, Trainer};
use mesh::Model;
use mesh::cancel::Cancel;
use std::ops::ControlFlow;
use std::time::Instant;

/// A GNG3D run prepared on one model. [`crate::Job`] trains it to the end
/// ([`GngRun::train`]); a front end that shows the network growing steps its
/// [`GngRun::trainer_mut`] itself, then calls [`GngRun::finish`] as the job does.
pub struct GngRun {
    trainer: Trainer,
    options: GngOptions,
    method: Method,
    /// The input's materials and origin (no mesh, no attributes): where the output goes.
    place: Model,
    started: Instant,
}

impl GngRun {
    /// Prepare `request` (a GNG3D method) on `input`: [`Request::gng_options`] resolved against
    /// the mesh, the trainer built (with attributes, the output's triangles follow their seams).
    pub fn new(input: &Model, request: &Request) -> Result<GngRun, JobError> {
        GngRun::tuned(input, request, |_| {}, |_| {})
    }

    /// [`GngRun::new`] with a front end's own settings over the request's: `options` edits
    /// the options before their one resolution against the mesh (λ, the signal budget, the
    /// step switches), `params` the resolved parameters before the trainer is built (the
    /// network's low-level knobs, which have no option).
    pub fn tuned(
        input: &Model,
        request: &Request,
        options: impl FnOnce(&mut GngOptions),
        params: impl FnOnce(&mut GngParams),
    ) -> Result<GngRun, JobError> {
        let mut gng = request.gng_options()?;
        options(&mut gng);
        let mut resolved = gng.resolve(&input.mesh)?;
        params(&mut resolved);
        // The run's clock starts with the trainer (its tables are part of the run).
        let started = Instant::now();
        let trainer = Trainer::new(input, resolved)?;
        Ok(GngRun {
            trainer,
            options: gng,
            method: request.method,
            place: Model {
                materials: input.materials.clone(),
                origin: input.origin,
                ..Model::default()
            },
            started,
        })
    }

    /// The trainer.
    pub fn trainer(&self) -> &Trainer {
        &self.trainer
    }

    /// The trainer, to step it.
    pub fn trainer_mut(&mut self) -> &mut Trainer {
        &mut self.trainer
    }

    /// Train to the end in the rounds every front end uses ([`Trainer::train_to_end`]),
    /// `observer` seeing each.
    pub fn train(&mut self, observer: &mut dyn Observer) {
        let budget = self.trainer.stats().max_signals;
        self.trainer.train_to_end(|p| {
            observer.training(p, budget);
            ControlFlow::Continue(())
        });
    }

    /// The run after training on the network as it is ([`gng3d_core::finish`], or
    /// [`gng3d_core::finish_cancellable`] with `cancel`): the output model in the input's place
    /// with its attributes, the summary (seconds from [`GngRun::new`]) and the warnings.
    pub fn finish(
        &self,
        cancel: Option<&Cancel>,
        on_step: impl FnMut(&StepRecord),
    ) -> Result<Outcome, JobError> {
        let result = match cancel {
            Some(cancel) => gng3d_core::finish_cancellable(&self.trainer, cancel, on_step),
            None => gng3d_core::finish(&self.trainer, on_step),
        }?;
        let seconds = self.started.elapsed().as_secs_f64();
        Ok(Outcome::of_gng(
            &self.place,
            self.method,
            &self.trainer,
            &self.options,
            result,
            seconds,
        ))
    }
}
