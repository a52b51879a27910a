#include "cutdyn/io/plot.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "case_fields.hpp"
#include "cutdyn/core/error.hpp"

namespace cutdyn::io {
namespace fs = std::filesystem;

namespace {

struct FigureFormat {
  std::string_view extension;
  std::string_view terminal;  // the gnuplot terminal
  double width, height;       // of a figure of one panel
  std::string_view unit;      // of the size: "" (pixels) or "in"
  std::string_view options;   // the `set terminal` arguments after the size
};

// Sizes chosen for a readable figure on screen (svg, png) and in a document (pdf).
constexpr FigureFormat kFormats[] = {
    {".svg", "svg", 900, 600, "", "dynamic enhanced font 'Sans,12' background rgb 'white'"},
    {".png", "pngcairo", 1200, 800, "", "enhanced font 'Sans,12'"},
    {".pdf", "pdfcairo", 7, 4.5, "in", "enhanced font 'Sans,10'"},
};

// Each panel after the first adds this share of a one-panel figure's height.
constexpr double kPanelHeight = 0.6;

// Okabe-Ito colours: distinct for colour-blind readers and in greyscale print.
constexpr std::string_view kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                         "#E69F00", "#56B4E9", "#000000"};

constexpr std::string_view kStyles[] = {"lines",         "points", "linespoints",
                                        "stable-region", "dashed", "marker"};

const FigureFormat* find_format(const fs::path& figure) {
  std::string extension = figure.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const FigureFormat& format : kFormats) {
    if (format.extension == extension) return &format;
  }
  return nullptr;
}

// The `set terminal` arguments for a figure of `panels` panels.
std::string terminal(const FigureFormat& format, std::size_t panels) {
  const double height =
      format.height * (1.0 + kPanelHeight * static_cast<double>(panels > 0 ? panels - 1 : 0));
  const std::string unit(format.unit);
  return std::string(format.terminal) + " size " + format_number(format.width) + unit + "," +
         format_number(std::round(height * 10.0) / 10.0) + unit + " " + std::string(format.options);
}

// A gnuplot double-quoted string holding `text` literally. Backquotes must be escaped:
// gnuplot runs `...` as a shell command even inside double quotes.
std::string quote(std::string_view text) {
  std::string quoted = "\"";
  for (char c : text) {
    switch (c) {
      case '\\':
        quoted += "\\\\";
        break;
      case '"':
        quoted += "\\\"";
        break;
      case '`':
        quoted += "\\140";
        break;
      case '\n':
        quoted += "\\n";
        break;
      case '\t':
        quoted += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f) quoted += c;  // drop controls
    }
  }
  return quoted + "\"";
}

// Text shown in the figure: quoted, and kept out of enhanced-text markup (where _ ^ @ & ~
// { } \ would mean subscripts and the like) when it holds any of those characters.
std::string label(std::string_view text) {
  const bool markup = text.find_first_of("_^@&~{}\\") != std::string_view::npos;
  return quote(text) + (markup ? " noenhanced" : "");
}

// Text in a `#` comment: one line.
std::string comment(std::string_view text) {
  std::string line(text);
  std::replace_if(
      line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return line;
}

std::string data_value(double value) { return std::isfinite(value) ? format_number(value) : "NaN"; }

void check_panel(const PlotSpec& spec) {
  if (spec.series.empty()) throw std::logic_error("write_plot: no series to plot");
  for (const PlotSeries& series : spec.series) {
    if (series.x.size() != series.y.size()) {
      throw std::logic_error("write_plot: series \"" + series.title + "\" has " +
                             std::to_string(series.x.size()) + " x values but " +
                             std::to_string(series.y.size()) + " y values");
    }
    const bool hex_colour = series.color.size() == 7 && series.color[0] == '#' &&
                            std::all_of(series.color.begin() + 1, series.color.end(),
                                        [](unsigned char c) { return std::isxdigit(c) != 0; });
    if (!series.color.empty() && !hex_colour) {
      throw std::logic_error("write_plot: series \"" + series.title + "\" has colour \"" +
                             series.color + "\" (use #rrggbb)");
    }
    if (std::find(std::begin(kStyles), std::end(kStyles), series.style) == std::end(kStyles)) {
      throw std::logic_error(
          "write_plot: series \"" + series.title + "\" has unknown style \"" + series.style +
          "\" (use lines, points, linespoints, stable-region, dashed or marker)");
    }
  }
  for (const PlotMark& mark : spec.x_marks) {
    if (!std::isfinite(mark.x)) throw std::logic_error("write_plot: non-finite x mark");
  }
  for (const std::optional<double>& bound : {spec.y_min, spec.y_max}) {
    if (bound && !std::isfinite(*bound)) throw std::logic_error("write_plot: non-finite y range");
  }
  if (spec.y_min && spec.y_max && !(*spec.y_min < *spec.y_max)) {
    throw std::logic_error("write_plot: y_min must be less than y_max");
  }
  if (spec.y_log && spec.y_min && !(*spec.y_min > 0.0)) {
    throw std::logic_error("write_plot: a logarithmic y axis needs y_min > 0");
  }
}

void check_figure(const PlotFigure& figure) {
  if (figure.panels.empty()) throw std::logic_error("write_plot: no panel to draw");
  for (const PlotSpec& panel : figure.panels) check_panel(panel);
}

bool has_finite_point(const PlotSpec& spec) {
  for (const PlotSeries& series : spec.series) {
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      if (std::isfinite(series.x[i]) && std::isfinite(series.y[i])) return true;
    }
  }
  return false;
}

std::string bound(const std::optional<double>& value) {
  return value ? format_number(*value) : std::string("*");
}

void write_data(std::ostream& out, const PlotFigure& figure, const std::string& figure_name,
                const std::string& script_name) {
  if (!figure.title.empty()) out << "# " << comment(figure.title) << '\n';
  out << "# Data for " << comment(figure_name) << ", drawn by " << comment(script_name)
      << ": one block per series\n"
      << "# (gnuplot `index 0`, `index 1`, ...), blocks separated by two blank lines;"
         " NaN marks a missing value.\n";
  const bool panels = figure.panels.size() > 1;
  std::size_t block = 0;
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const PlotSpec& spec = figure.panels[p];
    const std::string x_name = spec.x_label.empty() ? "x" : comment(spec.x_label);
    for (std::size_t s = 0; s < spec.series.size(); ++s, ++block) {
      const PlotSeries& series = spec.series[s];
      if (block > 0) out << "\n\n";
      if (panels && s == 0) {
        out << "# panel " << p + 1 << " of " << figure.panels.size()
            << (spec.title.empty() ? std::string() : ": " + comment(spec.title)) << '\n';
      }
      if (s == 0) {
        for (const PlotMark& mark : spec.x_marks)
          out << "# mark at " << x_name << " = " << data_value(mark.x) << ": "
              << comment(mark.label) << '\n';
      }
      const std::string& y_label = series.y2 ? spec.y2_label : spec.y_label;
      const std::string y_name = y_label.empty() ? "y" : comment(y_label);
      out << "# " << (series.title.empty() ? "series " + std::to_string(s) : comment(series.title))
          << '\n';
      out << "# columns: 1 = " << x_name << ", 2 = " << y_name << '\n';
      // An empty block would vanish between the separators and shift every later index.
      if (series.x.empty()) out << "NaN NaN\n";
      for (std::size_t i = 0; i < series.x.size(); ++i) {
        out << data_value(series.x[i]) << ' ' << data_value(series.y[i]) << '\n';
      }
    }
  }
}

// The settings and the plot command of one panel; its series are the data's blocks from
// `first_block` on. In a figure of several panels, `reset` clears what the panel before
// set.
void write_panel(std::ostream& out, const PlotSpec& spec, std::size_t first_block, bool reset) {
  if (reset) {
    out << "unset arrow\nunset label\nunset logscale\nunset y2tics\nunset y2label\n"
        << "unset mytics\n";
  }
  out << "set title " << label(spec.title) << '\n'
      << "set xlabel " << label(spec.x_label) << '\n'
      << "set ylabel " << label(spec.y_label) << '\n';
  const bool any_data = has_finite_point(spec);
  if (any_data) {
    out << "set autoscale xfix                # x axis spans the data exactly\n"
        << "set yrange [" << bound(spec.y_min) << ":" << bound(spec.y_max) << "]\n";
  } else {
    // Nothing to autoscale on: fixed ranges, so gnuplot draws empty axes instead of failing.
    double lo = spec.y_min.value_or(spec.y_log ? 1.0 : 0.0);
    const double hi = spec.y_max.value_or(spec.y_log ? lo * 10.0 : lo + 1.0);
    if (!(hi > lo)) lo = spec.y_log ? hi / 10.0 : hi - 1.0;
    out << "set xrange [0:1]                  # no data points\n"
        << "set yrange [" << format_number(lo) << ":" << format_number(hi) << "]\n";
  }
  if (spec.y_log) {
    // Decades are far apart: a fainter grid at the minor tics helps to read values off.
    out << "set logscale y\n"
        << "set mytics 10\n"
        << "set grid xtics ytics mytics linetype 1 linecolor rgb '#dcdcdc' linewidth 1, \\\n"
        << "         linetype 1 linecolor rgb '#f0f0f0' linewidth 1\n";
  } else {
    out << "set grid xtics ytics linetype 1 linecolor rgb '#dcdcdc' linewidth 1\n";
  }
  const bool right_axis =
      std::any_of(spec.series.begin(), spec.series.end(), [](const PlotSeries& p) { return p.y2; });
  if (right_axis) {
    out << "set y2label " << label(spec.y2_label) << '\n' << "set y2tics\n";
    if (any_data) {
      out << "set y2range [*:*]\n";
    } else {
      out << "set y2range [0:1]\n";
    }
  }
  if (any_data && std::any_of(spec.series.begin(), spec.series.end(),
                              [](const PlotSeries& p) { return p.style == "marker"; })) {
    out << "set offsets graph 0.02, graph 0.02, 0, 0  # room for a marker at either end\n";
  } else if (reset) {
    out << "set offsets 0, 0, 0, 0\n";
  }
  out << "set tics nomirror out\n"
      << "set border " << (right_axis ? 11 : 3) << " linewidth 1.2\n"
      << "# The key below the axes, never over the data\n"
      << "set key outside below center horizontal reverse Left nobox samplen 3 spacing 1.2 "
         "width 2\n";
  if (any_data && !spec.x_marks.empty()) {
    // A label beside its line, on the side with more room.
    double lo = INFINITY, hi = -INFINITY;
    for (const PlotSeries& series : spec.series) {
      for (std::size_t i = 0; i < series.x.size(); ++i) {
        if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) continue;
        lo = std::min(lo, series.x[i]);
        hi = std::max(hi, series.x[i]);
      }
    }
    out << "# Marks: vertical lines with their labels (on a white box, readable over data)\n"
        << "set style textbox opaque noborder\n";
    for (const PlotMark& mark : spec.x_marks) {
      const std::string x = format_number(mark.x);
      out << "set arrow from first " << x << ", graph 0 to first " << x
          << ", graph 1 nohead dashtype 2 linecolor rgb '#444444' linewidth 1.5 front\n";
      if (!mark.label.empty()) {
        const bool right_half = mark.x > 0.5 * (lo + hi);
        out << "set label " << label(mark.label) << " at first " << x
            << ", graph 1 offset character " << (right_half ? "-0.5" : "0.5") << ", character -1 "
            << (right_half ? "right" : "left") << " front boxed textcolor rgb '#222222'\n";
      }
    }
  }
  out << '\n';

  out << "# One colour per series\n";
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    const std::string_view colour =
        spec.series[s].color.empty() ? kPalette[s % std::size(kPalette)] : spec.series[s].color;
    out << "set style line " << s + 1 << " linecolor rgb '" << colour
        << "' linewidth 2 pointtype 7 pointsize 0.8\n";
  }
  out << "# Stable regions: a light, transparent fill beneath the boundary line\n"
      << "set style fill transparent solid 0.2 noborder\n\n";

  std::vector<std::string> items;
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    const PlotSeries& series = spec.series[s];
    const std::string source = "data index " + std::to_string(first_block + s) + " using 1:2" +
                               (series.y2 ? " axes x1y2" : "");
    const std::string line_style = " linestyle " + std::to_string(s + 1);
    const std::string title = series.title.empty() ? " notitle" : " title " + label(series.title);
    if (series.style == "stable-region") {
      // Fill down to y = 0 (to the bottom of the axis on a log scale, where 0 is undefined);
      // the key shows the shaded area, the line is drawn over it.
      items.push_back(source + " with filledcurves " + (spec.y_log ? "x1" : "y1=0") + line_style +
                      title);
      items.push_back(source + " with lines" + line_style + " notitle");
    } else if (series.style == "dashed") {
      items.push_back(source + " with lines" + line_style + " dashtype 2" + title);
    } else if (series.style == "marker") {
      items.push_back(source + " with points" + line_style + " pointtype 7 pointsize 2.2" + title);
    } else {
      items.push_back(source + " with " + series.style + line_style + title);
    }
  }
  out << "plot ";
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out << ", \\\n     ";
    out << items[i];
  }
  out << "\n";
}

void write_script(std::ostream& out, const PlotFigure& figure, const FigureFormat& format,
                  const std::string& figure_name, const std::string& data_name,
                  const std::string& script_name) {
  out << "# " << (figure.title.empty() ? std::string("cutdyn figure") : comment(figure.title))
      << "\n#\n"
      << "# Written by cutdyn. Draws " << comment(figure_name) << " from " << comment(data_name)
      << " (one block per series, read\n"
      << "# with `index 0`, `index 1`, ...). Restyle as you like, then run `gnuplot "
      << comment(script_name) << "` in this folder.\n\n";

  out << "set encoding utf8\n"
      << "set terminal " << terminal(format, figure.panels.size()) << '\n'
      << "set output " << quote(figure_name) << '\n'
      << "data = " << quote(data_name) << "\n\n";

  if (figure.panels.size() == 1) {
    out << "# Title and axes\n";
    write_panel(out, figure.panels.front(), 0, false);
  } else {
    const bool right_axis =
        std::any_of(figure.panels.begin(), figure.panels.end(), [](const PlotSpec& panel) {
          return std::any_of(panel.series.begin(), panel.series.end(),
                             [](const PlotSeries& p) { return p.y2; });
        });
    out << "# " << figure.panels.size() << " panels, top to bottom, under one title; fixed "
        << "side margins line their axes up\n"
        << "set multiplot layout " << figure.panels.size() << ",1 title " << label(figure.title)
        << " font ',14'\n"
        << "set lmargin 12\n"
        << "set rmargin " << (right_axis ? 12 : 4) << "\n";
    std::size_t block = 0;
    for (std::size_t p = 0; p < figure.panels.size(); ++p) {
      out << "\n# Panel " << p + 1 << ": " << comment(figure.panels[p].title) << '\n';
      write_panel(out, figure.panels[p], block, p > 0);
      block += figure.panels[p].series.size();
    }
    out << "unset multiplot\n";
  }
  out << "\nunset output\n";
}

void write_file(const fs::path& path, const fs::path& figure,
                const std::function<void(std::ostream&)>& body) {
  std::ofstream out(path);
  if (out) body(out);
  out.close();
  if (!out)
    throw std::runtime_error("cannot write " + path.string() + " (for " + figure.string() + ")");
}

std::optional<fs::path> find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string_view rest = path ? path : "/usr/local/bin:/usr/bin:/bin";
  while (true) {
    const std::size_t colon = rest.find(':');
    std::string_view folder = rest.substr(0, colon);
    fs::path candidate = fs::path(folder.empty() ? "." : std::string(folder)) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) {
      return fs::absolute(candidate, ec);  // absolute: the child changes folder before exec
    }
    if (colon == std::string_view::npos) return std::nullopt;
    rest.remove_prefix(colon + 1);
  }
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  constexpr std::size_t kMaxLength = 4000;
  if (text.size() > kMaxLength) text = "..." + text.substr(text.size() - kMaxLength);
  return text;
}

// Runs `gnuplot -d <script>` in `folder` (-d: ignore the user's ~/.gnuplot, for a
// reproducible figure), stdin and stdout on /dev/null, stderr into `stderr_file`.
// Returns the wait status.
int run_gnuplot(const fs::path& gnuplot, const fs::path& folder, const std::string& script,
                const fs::path& stderr_file) {
  // Everything the child needs is prepared before fork: after it, only
  // async-signal-safe calls.
  const std::string program = gnuplot.string();
  const std::string folder_text = folder.string();
  const std::string stderr_text = stderr_file.string();
  std::string arg0 = "gnuplot", arg1 = "-d", arg2 = script;
  char* argv[] = {arg0.data(), arg1.data(), arg2.data(), nullptr};

  const pid_t pid = ::fork();
  if (pid < 0)
    throw std::runtime_error("cannot start gnuplot: " + std::generic_category().message(errno));
  if (pid == 0) {
    // Kept above 2, so that one dup2 cannot close another when cutdyn runs without stdin.
    const auto above_std = [](int fd) { return fd >= 0 && fd <= 2 ? ::fcntl(fd, F_DUPFD, 3) : fd; };
    const int err = above_std(::open(stderr_text.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644));
    const int null_in = above_std(::open("/dev/null", O_RDONLY));
    const int null_out = above_std(::open("/dev/null", O_WRONLY));
    if (err < 0 || null_in < 0 || null_out < 0) ::_exit(126);
    ::dup2(null_in, STDIN_FILENO);
    ::dup2(null_out, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    for (int fd : {err, null_in, null_out}) {
      if (fd > STDERR_FILENO) ::close(fd);
    }
    if (::chdir(folder_text.c_str()) != 0) {
      constexpr char kMessage[] = "cutdyn: cannot enter the scratch folder\n";
      [[maybe_unused]] auto n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
      ::_exit(126);
    }
    ::execv(program.c_str(), argv);
    constexpr char kMessage[] = "cutdyn: cannot execute gnuplot\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw std::runtime_error("cannot wait for gnuplot: " +
                               std::generic_category().message(errno));
    }
  }
  return status;
}

}  // namespace

void check_figure_path(const fs::path& figure) {
  if (find_format(figure)) return;
  const std::string extension = figure.extension().string();
  const std::string problem =
      extension.empty() ? "figure file name has no extension: use .svg, .png or .pdf"
                        : "unsupported figure format \"" + extension + "\": use .svg, .png or .pdf";
  throw InvalidInput({problem}, figure.string());
}

std::string case_key_label(const Case& c, std::string_view key) {
  return detail::key_axis_label(c, key);
}

PlotSeries envelope(const PlotSeries& series, std::size_t buckets) {
  const std::size_t n = series.x.size();
  if (buckets == 0 || n <= 2 * buckets || series.y.size() != n) return series;
  PlotSeries thin = series;
  thin.x.clear();
  thin.y.clear();
  const auto keep = [&](std::size_t i) {
    thin.x.push_back(series.x[i]);
    thin.y.push_back(series.y[i]);
  };
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t from = b * n / buckets, to = (b + 1) * n / buckets;
    std::optional<std::size_t> lo, hi, gap;
    for (std::size_t i = from; i < to; ++i) {
      const double y = series.y[i];
      if (!std::isfinite(y) || !std::isfinite(series.x[i])) {
        if (!gap) gap = i;
        continue;
      }
      if (!lo || y < series.y[*lo]) lo = i;
      if (!hi || y > series.y[*hi]) hi = i;
    }
    // The kept samples in their order: the lowest, the highest and the first gap.
    std::vector<std::size_t> kept;
    for (const std::optional<std::size_t>& i : {lo, hi, gap})
      if (i) kept.push_back(*i);
    std::sort(kept.begin(), kept.end());
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    for (std::size_t i : kept) keep(i);
  }
  return thin;
}

std::vector<fs::path> figure_files(const fs::path& figure) {
  const fs::path folder = figure.parent_path();
  const std::string stem = figure.stem().string();
  return {figure, folder / (stem + ".dat"), folder / (stem + ".gp")};
}

void write_plot(const PlotSpec& spec, const fs::path& figure, OutputTransaction& outputs) {
  write_plot(PlotFigure{spec.title, {spec}}, figure, outputs);
}

void write_plot(const PlotFigure& spec, const fs::path& figure, OutputTransaction& outputs) {
  check_figure_path(figure);
  check_figure(spec);
  const FigureFormat& format = *find_format(figure);

  const std::optional<fs::path> gnuplot = find_program("gnuplot");
  if (!gnuplot) {
    throw std::runtime_error("cannot draw " + figure.string() +
                             ": gnuplot is not installed (Debian package gnuplot-nox)");
  }

  // Final names, written in a scratch folder beside the figure so that the script's
  // relative names stay right after the files are renamed into place.
  const std::vector<fs::path> files = figure_files(figure);
  const std::string figure_name = files[0].filename().string();
  const std::string data_name = files[1].filename().string();
  const std::string script_name = files[2].filename().string();
  const fs::path scratch = outputs.scratch_dir(figure);

  write_file(scratch / data_name, figure,
             [&](std::ostream& out) { write_data(out, spec, figure_name, script_name); });
  write_file(scratch / script_name, figure, [&](std::ostream& out) {
    write_script(out, spec, format, figure_name, data_name, script_name);
  });

  const fs::path stderr_file = scratch / "gnuplot.stderr";
  const int status = run_gnuplot(*gnuplot, scratch, script_name, stderr_file);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                              : "signal " + std::to_string(WTERMSIG(status));
    const std::string message = read_text(stderr_file);
    throw std::runtime_error("gnuplot failed to draw " + figure.string() + " (" + how + ")" +
                             (message.empty() ? std::string() : ":\n" + message));
  }
  std::error_code ec;
  if (fs::file_size(scratch / figure_name, ec) == 0 || ec) {
    throw std::runtime_error("gnuplot wrote no figure for " + figure.string() +
                             (fs::exists(stderr_file) ? ": " + read_text(stderr_file) : ""));
  }

  outputs.adopt(scratch / figure_name, files[0]);
  outputs.adopt(scratch / data_name, files[1]);
  outputs.adopt(scratch / script_name, files[2]);
}

}  // namespace cutdyn::io
