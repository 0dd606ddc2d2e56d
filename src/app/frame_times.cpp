#include "app/frame_times.hpp"

#include <ostream>

#include "io/atomic_file.hpp"

namespace weft {

void FrameTimeLog::write(const std::string& path) const {
  write_file_atomically(path, [this](std::ostream& out) {
    out << "frame,start_s,work_ms,interval_ms,shown_step,step_ms,simulated_s\n";
    for (size_t i = 0; i < frames_.size(); ++i) {
      const FrameTime& f = frames_[i];
      out << i << ',' << f.start_s << ',' << f.work_ms << ',' << f.interval_ms << ',' << f.shown_step << ','
          << f.step_ms << ',' << f.simulated_s << '\n';
    }
  });
}

}  // namespace weft
