#include "ui/simulation_worker.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <utility>

namespace weft {

namespace {

// Wall time the worker may spend on steps before it publishes what it has (play()'s budget): a
// light scene then shows up at least this often, a heavy one after each step.
constexpr double publish_every_ms = 10.0;
// Rates are averaged over windows this long.
constexpr double rate_window_seconds = 0.5;

size_t checkpoint_bytes(const Checkpoint& checkpoint) {
  size_t bytes = sizeof(Checkpoint);
  for (const ClothCheckpoint& cloth : checkpoint.cloths) {
    bytes += sizeof(double) * static_cast<size_t>(cloth.x.size() + cloth.v.size() +
                                                  cloth.rest_positions.size() + cloth.membrane_rest.size());
  }
  return bytes + checkpoint.contact_pairs.size() * sizeof(checkpoint.contact_pairs[0]);
}

bool same_drag(const VertexDrag& a, const VertexDrag& b) {
  return a.active() == b.active() && a.cloth() == b.cloth() && a.vertex() == b.vertex();
}

}  // namespace

SimulationWorker::SimulationWorker(SimulationSession session, size_t history_bytes)
    : live_(std::move(session)),
      shown_(std::make_unique<SimulationSession>(live_.mirror())),
      history_limit_(history_bytes),
      back_(std::make_unique<SimulationSession>(live_.mirror())) {
  live_.before_step = [this](World& world) {
    if (live_.step_in_frame() == 0) remember_frame();
    live_drag_.apply(world);
  };
  thread_ = std::thread([this] { run(); });
}

SimulationWorker::~SimulationWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void SimulationWorker::submit(Command command) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    commands_.push_back(std::move(command));
    ++submitted_;
  }
  wake_.notify_one();
}

bool SimulationWorker::exchange(const VertexDrag& drag, double speed) {
  auto settings = std::make_unique<SessionSettings>(read_settings(*shown_, drag));
  bool changed = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = std::move(settings);
    speed_ = speed;
    if (back_fresh_) {
      back_fresh_ = false;
      changed = true;
      shown_rates_ = back_rates_;
      if (back_->generation() != shown_->generation()) {
        shown_ = std::move(back_);  // the worker makes the next mirror
      } else {
        // Play or pause sent but not yet run: the UI's choice stands until it has.
        const bool playing = applied_ < submitted_ ? shown_->playing : back_->playing;
        shown_->show_state_of(*back_);
        shown_->playing = playing;
      }
    }
  }
  wake_.notify_one();
  return changed;
}

void SimulationWorker::wait_for_commands() {
  std::unique_lock<std::mutex> lock(mutex_);
  const long target = submitted_;
  published_.wait(lock, [&] { return applied_ >= target; });
}

void SimulationWorker::remember_frame() {
  if (history_limit_ == 0) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (history_generation_ != live_.generation()) {
      history_.clear();  // another world's frames
      history_bytes_ = 0;
      history_generation_ = live_.generation();
    }
    if (!history_.empty() && history_.back()->frame >= live_.frame()) return;
  }
  auto checkpoint =
      std::make_shared<const Checkpoint>(capture_checkpoint(live_.world(), live_.frame(), "", 0.0));
  const size_t bytes = checkpoint_bytes(*checkpoint);
  std::lock_guard<std::mutex> lock(mutex_);
  history_.push_back(std::move(checkpoint));
  history_bytes_ += bytes;
  while (history_bytes_ > history_limit_ && !history_.empty()) {
    history_bytes_ -= checkpoint_bytes(*history_.front());
    history_.pop_front();
  }
}

HistoryRange SimulationWorker::history() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (history_.empty()) return {};
  return {history_.front()->frame, history_.back()->frame, history_bytes_};
}

std::shared_ptr<const Checkpoint> SimulationWorker::history_frame(int frame) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (history_.empty() || frame < history_.front()->frame || frame > history_.back()->frame) return nullptr;
  return history_[static_cast<size_t>(frame - history_.front()->frame)];
}

void SimulationWorker::resume_from(int frame) {
  std::shared_ptr<const Checkpoint> checkpoint = history_frame(frame);
  if (checkpoint == nullptr) return;
  submit([this, checkpoint](SimulationSession& session) {
    session.restart_from(*checkpoint);
    std::lock_guard<std::mutex> lock(mutex_);
    while (!history_.empty() && history_.back()->frame > checkpoint->frame) {
      history_bytes_ -= checkpoint_bytes(*history_.back());
      history_.pop_back();
    }
  });
}

void SimulationWorker::apply(const SessionSettings& settings) {
  if (!apply_settings(live_, settings)) return;  // read from a world since replaced
  if (same_drag(live_drag_, settings.drag)) {
    live_drag_.move_to(settings.drag.target());
    return;
  }
  if (live_drag_.active()) live_drag_.end(live_.world());
  live_drag_ = settings.drag;
}

void SimulationWorker::publish(long applied, const WorkerRates& rates) {
  if (live_.step_in_frame() == 0) remember_frame();  // the latest frame too, before its first step
  bool need_mirror = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    need_mirror = back_ == nullptr || back_->generation() != live_.generation();
  }
  // A new world's mirror copies every cloth: made outside the lock, so the UI does not wait.
  std::unique_ptr<SimulationSession> mirror;
  if (need_mirror) mirror = std::make_unique<SimulationSession>(live_.mirror());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (mirror != nullptr) {
      back_ = std::move(mirror);
    } else {
      back_->show_state_of(live_);
      back_->playing = live_.playing;
    }
    applied_ = applied;
    back_rates_ = rates;
    back_fresh_ = true;
  }
  published_.notify_all();
}

void SimulationWorker::run() {
  using Clock = std::chrono::steady_clock;
  Clock::time_point last = Clock::now();
  Clock::time_point window_start = last;
  int window_steps = 0;
  double window_time = 0.0;
  WorkerRates rates;
  long applied = 0;
  bool was_playing = false;
  for (;;) {
    std::deque<Command> commands;
    std::unique_ptr<SessionSettings> settings;
    double speed = 1.0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !commands_.empty() || pending_ != nullptr || live_.playing; });
      if (stop_) return;
      commands.swap(commands_);
      settings = std::move(pending_);
      speed = speed_;
    }
    const int generation = live_.generation();
    const double time_before = live_.world().time();
    const long applied_before = applied;
    int steps = 0;
    try {
      if (settings != nullptr) apply(*settings);
      for (Command& command : commands) {
        command(live_);
        ++applied;
      }
      if (live_.generation() != generation) live_drag_ = VertexDrag();  // the old world's vertex
      const Clock::time_point now = Clock::now();
      if (!was_playing) last = now;  // no debt from the time spent paused
      const double wall_seconds = std::min(std::chrono::duration<double>(now - last).count(), 0.25);
      last = now;
      was_playing = live_.playing;
      if (live_.playing) steps = live_.play(wall_seconds, speed, publish_every_ms);
    } catch (const std::exception& error) {
      // Nothing a step is expected to throw; the viewer stays open on the last good state.
      std::fprintf(stderr, "weft: the simulation stopped: %s\n", error.what());
      live_.playing = false;
      applied = applied_before + static_cast<long>(commands.size());  // so wait_for_commands returns
    }
    // Rates over a window of wall time (commands' steps count too).
    if (live_.generation() == generation) {
      window_steps += steps;
      window_time += live_.world().time() - time_before;
    }
    const Clock::time_point now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - window_start).count();
    if (elapsed >= rate_window_seconds) {
      rates = {window_steps / elapsed, window_time / elapsed};
      window_start = now;
      window_steps = 0;
      window_time = 0.0;
    }
    if (!live_.playing) rates = {};
    if (steps > 0 || !commands.empty() || live_.generation() != generation) publish(applied, rates);
    if (live_.playing && steps == 0) {
      // Ahead of real time: wait a little for the debt to grow (or a command).
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(1), [&] { return stop_ || !commands_.empty(); });
    }
  }
}

}  // namespace weft
