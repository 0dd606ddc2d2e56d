#pragma once
// The viewer's simulation on a thread of its own. The thread that draws (the UI) never waits for a
// step: it draws a mirror of the session (SimulationSession::mirror) holding the state of the last
// finished step, and it hands the worker commands (step, reset, play...) and the settings its
// panels edit on the mirror, which the worker applies between steps. No OpenGL and no ImGui.
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "ui/session_settings.hpp"
#include "ui/simulation_session.hpp"
#include "ui/vertex_drag.hpp"

namespace weft {

// The frames the worker keeps (its history): first to last, each a Checkpoint at the frame's start.
struct HistoryRange {
  int first = -1, last = -1;  // -1 when empty
  size_t bytes = 0;
  bool empty() const { return first < 0; }
};

// How fast the worker steps, measured on its own thread.
struct WorkerRates {
  double steps_per_second = 0.0;
  double real_time_factor = 0.0;  // simulated seconds per wall second while playing
};

class SimulationWorker {
 public:
  using Command = std::function<void(SimulationSession&)>;

  // Takes the session and starts the thread; the session's before_step is the worker's from now on.
  // It keeps the state at every frame's start, the latest frames up to `history_bytes` (0: none),
  // for the UI to scrub back through; a reset or another scene clears them.
  explicit SimulationWorker(SimulationSession session, size_t history_bytes = 256u << 20);
  // Stops after the step or command under way and joins the thread.
  ~SimulationWorker();
  SimulationWorker(const SimulationWorker&) = delete;
  SimulationWorker& operator=(const SimulationWorker&) = delete;

  // The UI's side; call from one thread only.

  // What to draw and what the panels edit: the state of the last step taken in (exchange), the
  // UI's own settings. Replaced by a new mirror when the worker's world is replaced (reset, load).
  SimulationSession& shown() { return *shown_; }
  // Queues `command` to run on the worker's session before its next step, after the commands
  // queued before it. A command that changes `playing` should change shown().playing too: the
  // worker's value is taken in only once every command sent has run.
  void submit(Command command);
  // Sends shown()'s settings and `drag` to the worker, for its next step, and takes in the last
  // finished step: returns true when shown() changed (new state, or a new mirror after a reset or
  // load). Never waits for a step.
  bool exchange(const VertexDrag& drag, double speed);
  // Waits until every command submitted has run and its result has been published, for exchange()
  // to take in (a screenshot run draws after a fixed number of frames; tests).
  void wait_for_commands();
  const WorkerRates& rates() const { return shown_rates_; }

  HistoryRange history() const;
  // The state at the start of `frame`, null when the history does not hold it.
  std::shared_ptr<const Checkpoint> history_frame(int frame) const;
  // Queues a restart from the history's `frame` (SimulationSession::restart_from): the frames after
  // it are dropped. Does nothing if the history does not hold it.
  void resume_from(int frame);
  size_t history_limit() const { return history_limit_; }

 private:
  void run();
  // Hands the worker's session to the UI: its state into back_, or a new mirror after a reset.
  void publish(long applied, const WorkerRates& rates);
  // The UI's settings and drag, if any came: applied to the worker's session before its step.
  void apply(const SessionSettings& settings);
  // The worker's session at a frame's start into the history (once per frame), oldest dropped.
  void remember_frame();

  SimulationSession live_;  // the worker thread's alone
  VertexDrag live_drag_;
  std::unique_ptr<SimulationSession> shown_;  // the UI thread's alone

  const size_t history_limit_;
  mutable std::mutex mutex_;           // guards everything below
  std::condition_variable wake_;       // the worker: commands, settings or stop
  std::condition_variable published_;  // finish_commands: a publication
  std::deque<Command> commands_;
  long submitted_ = 0;                        // commands submitted (the UI's count)
  long applied_ = 0;                          // commands run, as of the last publication
  std::unique_ptr<SessionSettings> pending_;  // the UI's latest settings, not yet applied
  double speed_ = 1.0;
  std::unique_ptr<SimulationSession> back_;  // the last published state (a mirror)
  bool back_fresh_ = false;                  // published since the UI last took it in
  WorkerRates back_rates_;
  bool stop_ = false;
  std::deque<std::shared_ptr<const Checkpoint>> history_;  // consecutive frames, oldest first
  size_t history_bytes_ = 0;
  int history_generation_ = -1;  // the world the history's frames belong to

  WorkerRates shown_rates_;  // the UI thread's copy
  std::thread thread_;       // last: starts once everything above exists
};

}  // namespace weft
