// vknerf.Trainer: steps with the GIL released; Trainer._train, the loop under Trainer.train
// (python/vknerf/_training.py), runs `vknerf train`'s schedule and stops at a step boundary on
// Ctrl-C, a callback's exception or a callback returning False.
#include <pybind11/stl.h>

#include <chrono>
#include <filesystem>
#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "errors.h"
#include "holders.h"

namespace py = pybind11;

namespace vknerf::python {

namespace {

py::dict statsDict(const StepStats& s) {
  py::dict d;
  d["step"] = s.step;
  d["rays"] = s.rays;
  d["samples"] = s.samples;
  if (s.hasLoss) {
    d["loss"] = s.loss;  // the fine pass's MSE over the batch
    d["psnr"] = s.psnr;
    py::dict terms;  // the other loss terms, by the configuration field that weighs each
    for (const auto& [name, value] : s.lossTerms) terms[py::str(name)] = value;
    d["loss_terms"] = terms;
  }
  return d;
}

StepStats stepLocked(TrainerState& t, bool readLoss, std::optional<double> fraction, bool setFraction) {
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(t.busy);
  if (setFraction) t.trainer->setRunProgress(fraction);
  return t.trainer->step(readLoss);
}

// train()'s steps run two deep, as `vknerf train`'s do (Trainer::submitStep): each call returns
// the statistics of the step before the one it submits.
std::optional<StepStats> submitLocked(TrainerState& t, bool readLoss, double fraction) {
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(t.busy);
  t.trainer->setRunProgress(fraction);
  return t.trainer->submitStep(readLoss);
}

std::optional<StepStats> finishLocked(TrainerState& t) {
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(t.busy);
  return t.trainer->finishSteps();
}

void save(TrainerState& t, const std::string& path) {
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(t.busy);
  aboutFile(std::filesystem::path(path).parent_path().empty() ? "." : std::filesystem::path(path).parent_path().string(),
            [&] { t.trainer->save(path); });
}

// `vknerf train --steps N / --time S`'s loop: the learning rates decay over the run's budget
// (Trainer::setRunProgress), the loss is read every `logEvery` steps and on the last, and the
// time excludes compiling kernels. Each step first runs Python's signal handlers (Ctrl-C raises
// KeyboardInterrupt there), between steps, with the GIL held. On any exception the trainer stops
// at that step boundary, saves to `checkpoint` when one is named, and the exception goes on.
py::dict train(TrainerState& t, uint32_t steps, double seconds, uint32_t logEvery, const py::object& report,
               const std::optional<std::string>& checkpoint) {
  if (steps == 0 && !(seconds > 0)) throw InvalidArgument("train needs steps > 0 or time > 0 (seconds)");
  if (logEvery == 0) throw InvalidArgument("log_every must be at least 1");
  Trainer& trainer = *t.trainer;
  const uint32_t first = trainer.steps();
  if (uint64_t(first) + steps > UINT32_MAX) throw InvalidArgument("steps passes the step counter's limit");
  const uint32_t last = steps ? first + steps : UINT32_MAX;
  const auto t0 = std::chrono::steady_clock::now();
  const double compiledBefore = t.ctx->compileStats().seconds;
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() -
           (t.ctx->compileStats().seconds - compiledBefore);
  };
  const auto runFraction = [&] {
    const double s = elapsed(), done = double(trainer.steps() - first);
    if (steps && seconds > 0) return std::max(done / steps, s / seconds);
    return steps ? done / steps : s / seconds;
  };
  py::dict summary;
  bool stoppedByCallback = false;
  // A step's statistics arrive once the next step is submitted (or the loop ends); the report
  // callback sees each report step's loss then. Returns false when the callback stops the run.
  const auto reported = [&](const std::optional<StepStats>& st) {
    if (!st || !st->hasLoss) return true;
    summary["loss"] = st->loss, summary["psnr"] = st->psnr;
    if (report.is_none()) return true;
    py::dict d = statsDict(*st);
    d["elapsed"] = elapsed();
    d["fraction"] = std::min(1.0, runFraction());
    return !report(d).equal(py::bool_(false));
  };
  try {
    while (trainer.steps() < last && !(seconds > 0 && elapsed() >= seconds)) {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      const bool reportStep = (trainer.steps() + 1) % logEvery == 0 || trainer.steps() + 1 == last;
      if (!reported(submitLocked(t, reportStep, runFraction()))) {
        stoppedByCallback = true;
        break;
      }
    }
    if (!reported(finishLocked(t))) stoppedByCallback = true;
  } catch (...) {
    if (checkpoint) save(t, *checkpoint);
    throw;
  }
  if (checkpoint) save(t, *checkpoint);
  summary["steps"] = trainer.steps() - first;
  summary["step"] = trainer.steps();
  summary["seconds"] = elapsed();
  summary["stopped_by_callback"] = stoppedByCallback;
  return summary;
}

}  // namespace

void bindTrainer(py::module_& m) {
  py::class_<PyTrainer>(m, "Trainer", "Fits a model to a dataset on the context's device.")
      .def(py::init([](const PyContext& ctx, const PyDataset& data, const TrainConfig& config) {
             auto state = std::make_shared<TrainerState>();
             state->ctx = ctx.ctx;
             py::gil_scoped_release release;
             state->trainer = std::make_unique<Trainer>(ctx.ctx, *data.data, config);
             return PyTrainer{state};
           }),
           py::arg("context"), py::arg("dataset"), py::arg("config"))
      .def("step", [](PyTrainer& t, uint32_t n, bool readLoss) {
             if (n == 0) throw InvalidArgument("step needs n >= 1");
             StepStats st;
             for (uint32_t i = 0; i < n; ++i) {
               if (PyErr_CheckSignals() != 0) throw py::error_already_set();
               st = stepLocked(*t.state, readLoss && i + 1 == n, std::nullopt, false);
             }
             return statsDict(st);
           },
           py::arg("n") = 1, py::arg("read_loss") = true,
           "n optimisation steps (the learning rates follow the step count over decay_steps); the last "
           "step's stats: step, rays, samples, and with read_loss loss (MSE) and psnr.")
      .def("_train", [](PyTrainer& t, uint32_t steps, double seconds, uint32_t logEvery, const py::object& report,
                        const std::optional<std::string>& checkpoint) {
             return train(*t.state, steps, seconds, logEvery, report, checkpoint);
           },
           py::arg("steps"), py::arg("seconds"), py::arg("log_every"), py::arg("report"), py::arg("checkpoint"))
      .def_property_readonly("steps", [](const PyTrainer& t) { return t.state->trainer->steps(); })
      .def_property_readonly("learning_rate", [](const PyTrainer& t) { return t.state->trainer->learningRate(); })
      .def_property_readonly("config", [](const PyTrainer& t) { return t.state->trainer->model().config(); })
      .def_property_readonly("capacity_note", [](const PyTrainer& t) { return t.state->trainer->capacityNote(); })
      .def("save", [](PyTrainer& t, const std::string& path) { save(*t.state, path); }, py::arg("path"),
           "Checkpoint (config, parameters, Adam state, step, training cameras), written atomically.")
      .def("resume", [](PyTrainer& t, const std::string& path) {
             py::gil_scoped_release release;
             std::lock_guard<std::mutex> lock(t.state->busy);
             aboutFile(path, [&] { t.state->trainer->resume(path); });
           }, py::arg("path"))
      .def("cameras", [](const PyTrainer& t) {
             std::lock_guard<std::mutex> lock(t.state->busy);
             return t.state->trainer->cameras();
           }, "The training cameras as the model is fitted through them (refined when the fast model refines cameras).")
      .def("poses", [](const PyTrainer& t) {
             std::lock_guard<std::mutex> lock(t.state->busy);
             std::vector<float> out;
             const auto cameras = t.state->trainer->cameras();
             for (const Camera& c : cameras) out.insert(out.end(), c.c2w.begin(), c.c2w.end());
             return toArray(std::move(out), {py::ssize_t(cameras.size()), 4, 4});
           }, "(N, 4, 4) float32: cameras()' poses")
      .def_static("config_of", [](const std::string& path) { return aboutFile(path, [&] { return Trainer::configOf(path); }); });
}

}  // namespace vknerf::python
