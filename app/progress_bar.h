// A one-line progress bar with ETA on stderr, drawn only when stderr is a terminal.
#pragma once

#include <string>

namespace caustica {

/// Redraws "[#####.....]  45%  3.2 s  ETA 4.1 s  stage" in place.
class ProgressBar {
public:
    /// Draws nothing when `enabled` is false or stderr is not a terminal.
    explicit ProgressBar(bool enabled);
    ~ProgressBar();

    /// Updates the bar; `fraction` in [0, 1].
    void update(double fraction, double elapsed_seconds, const std::string& stage);

    /// Erases the bar so that following output starts on a clean line.
    void finish();

private:
    bool active_;
    bool drawn_ = false;
};

}  // namespace caustica
