#pragma once
// Text as a gnuplot single-quoted string (a quote inside doubles), for the scripts the plot
// writers (app/plot.cpp, bench/tradeoff.cpp) hand to gnuplot: file names and titles may hold
// quotes, backslashes and spaces, which a single-quoted string takes literally.
#include <string>

namespace weft {

std::string gnuplot_quote(const std::string& text);

}  // namespace weft
