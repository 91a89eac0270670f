// The command line's own values, checked as the scene's keys are: one line naming the flag,
// in the format of docs/cli.md (`svetlo: error: SCENE: --spp: must be >= 1 (is 0)`).
#pragma once

#include <string>

namespace svetlo {

/// The whole number `text` given to `flag` (for a run of the scene `file`), in [lo, hi].
/// Throws Error(file, flag, ...) otherwise.
long long flag_integer(const std::string& file, const std::string& flag, const std::string& text,
                       long long lo, long long hi);

/// A number of seconds given to `flag`: empty is 0 (none); otherwise a finite number > 0 and at
/// most a week.
double flag_seconds(const std::string& file, const std::string& flag, const std::string& text);

/// The longest time budget, seconds: a week (--time, Python's `time`).
inline constexpr double kMaxSeconds = 7.0 * 24.0 * 3600.0;

/// The largest thread count a flag may ask for; more than the machine's cores run on its cores.
inline constexpr long long kMaxThreads = 4096;

}  // namespace svetlo
