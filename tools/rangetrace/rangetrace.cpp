// Running POV-Ray: a private temporary directory (Debian's povray.conf allows reads and writes
// in "." and /tmp; includes come through +L), parallel processes over the views, decoding.
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <thread>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "rangetrace/rangetrace.h"

namespace canopy::rangetrace {

using common::Error;

namespace {

// A private directory under $TMPDIR (or /tmp), removed with its files on destruction.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/rangetrace-XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (mkdtemp(buf.data()) == nullptr) {
      throw Error("cannot create a temporary directory in " + templ + ": " + std::strerror(errno));
    }
    path_ = buf.data();
  }
  ~TempDir() {
    for (const auto& f : files()) ::unlink((path_ + "/" + f).c_str());
    ::rmdir(path_.c_str());
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    if (DIR* d = ::opendir(path_.c_str())) {
      while (dirent* e = ::readdir(d)) {
        const std::string n = e->d_name;
        if (n != "." && n != "..") out.push_back(n);
      }
      ::closedir(d);
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  std::string path_;
};

// POV-Ray's own error lines from its console log: from the first line that mentions an error,
// with its 80-column wrapping undone.
std::string povray_message(const std::string& log) {
  std::istringstream in(log);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::size_t first = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find("Error") != std::string::npos || lines[i].find("error") != std::string::npos) {
      first = i;
      break;
    }
  }
  if (first == lines.size()) first = lines.size() > 8 ? lines.size() - 8 : 0;
  // A wrapped line continues with a leading space: start at the beginning of the message.
  while (first > 0 && lines[first].rfind(' ', 0) == 0) --first;
  std::string msg;
  for (std::size_t i = first; i < lines.size(); ++i) {
    if (lines[i].find_first_not_of(' ') == std::string::npos) continue;
    if (!msg.empty()) msg += lines[i].rfind(' ', 0) == 0 ? "" : "\n  ";
    msg += lines[i];
  }
  return msg;
}

// Runs povray with `args` in directory `dir`, console output to `log_name` there.
// Throws Error with POV-Ray's message when it fails.
void run_povray(const Params& params, const std::string& dir, std::vector<std::string> args,
                const std::string& log_name) {
  args.insert(args.begin(), params.povray);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log_path = dir + "/" + log_name;
  const pid_t pid = ::fork();
  if (pid < 0) throw Error(std::string("cannot start POV-Ray: fork: ") + std::strerror(errno));
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec.
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int null_fd = ::open("/dev/null", O_RDONLY);
    if (fd < 0 || null_fd < 0 || ::chdir(dir.c_str()) != 0) ::_exit(126);
    ::dup2(null_fd, 0);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error(std::string("waitpid: ") + std::strerror(errno));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    throw Error("cannot run POV-Ray '" + params.povray + "' (is the Debian package povray installed?)");
  }
  std::string log;
  try {
    log = common::read_file(log_path);
  } catch (const Error&) {
  }
  throw Error("POV-Ray failed: " + povray_message(log));
}

std::vector<std::string> common_args(const Model& model) {
  std::vector<std::string> args = {"-D", "-P", "-V", "+WT1"};
  if (!model.include_dir.empty()) args.push_back("+L" + model.include_dir);
  return args;
}

// The model's bounding box (world frame) from POV-Ray's min_extent/max_extent.
std::pair<Eigen::Vector3d, Eigen::Vector3d> model_extent(const Model& model, const Params& params,
                                                         const TempDir& tmp) {
  std::string pov = "#version 3.7;\n";
  pov += model.include_dir.empty() ? model.inline_code : "#include \"" + model.include_file + "\"\n";
  pov += "#ifndef (Vehicle)\n#error \"the model does not declare Vehicle\"\n#end\n";
  pov += "#fopen ExtentFile \"extent.txt\" write\n";
  pov += "#write (ExtentFile, vstr(3, min_extent(Vehicle), \" \", 0, 9), \" \", "
         "vstr(3, max_extent(Vehicle), \" \", 0, 9), \"\\n\")\n#fclose ExtentFile\n";
  common::write_file_atomic(tmp.path() + "/extent.pov", pov);
  auto args = common_args(model);
  args.insert(args.end(), {"+W1", "+H1", "-F", "+Iextent.pov"});
  run_povray(params, tmp.path(), args, "extent.log");
  std::istringstream in(common::read_file(tmp.path() + "/extent.txt"));
  Eigen::Vector3d lo, hi;
  if (!(in >> lo.x() >> lo.y() >> lo.z() >> hi.x() >> hi.y() >> hi.z())) {
    throw Error("cannot read the model's extent from POV-Ray");
  }
  if (!(lo.array() < hi.array()).all() || lo.cwiseAbs().maxCoeff() > 1e5 ||
      hi.cwiseAbs().maxCoeff() > 1e5) {
    throw Error("model '" + model.name + "': Vehicle is empty, flat or unbounded (extent " +
                std::to_string(lo.x()) + ".." + std::to_string(hi.x()) + ")");
  }
  // pov_frame is a permutation of axes, so it maps the box corners to the box corners.
  return {pov_frame(lo), pov_frame(hi)};
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> model_bounds(const Model& model, const Params& params) {
  TempDir tmp;
  return model_extent(model, params, tmp);
}

formats::PointCloud run(const Model& model, const SceneRecipe& scene, const Params& params) {
  if (params.size < 1 || !(params.spacing > 0)) throw common::UsageError("--size and --spacing must be > 0");
  TempDir tmp;
  common::log::Phase prep("model");
  const auto [lo, hi] = model_extent(model, params, tmp);
  const Placement placement = place(lo, hi, params.pose);
  const Encoding enc = encoding_for(placement, params);
  const std::vector<Disc> foliage = make_foliage(scene, params.pose, placement.top, params.seed);
  char dims[160];
  std::snprintf(dims, sizeof dims, "%s %.3f x %.3f x %.3f m, %zu foliage discs", model.name.c_str(),
                hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(), foliage.size());
  prep.done(dims);

  common::log::Phase render("render");
  common::write_file_atomic(tmp.path() + "/scene.pov",
                            scene_pov(model, placement, enc, scene.views, foliage, params));
  const int views = static_cast<int>(scene.views.size());
  const int workers = std::max(1, std::min(params.threads, views));
  std::vector<std::string> errors(workers);
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) {
    // Contiguous blocks of views; frames 2k (coordinates) and 2k+1 (labels) of view k.
    const int first = views * w / workers, last = views * (w + 1) / workers - 1;
    pool.emplace_back([&, w, first, last] {
      auto args = common_args(model);
      const std::string size = std::to_string(params.size);
      args.insert(args.end(), {"+W" + size, "+H" + size, "-A", "+FP16", "File_Gamma=1.0",
                               "+Iscene.pov", "+Of.ppm", "+KFI0",
                               "+KFF" + std::to_string(2 * views - 1), "+KI0",
                               "+KF" + std::to_string(2 * views - 1),
                               "+SF" + std::to_string(2 * first), "+EF" + std::to_string(2 * last + 1)});
      try {
        run_povray(params, tmp.path(), args, "render" + std::to_string(w) + ".log");
      } catch (const std::exception& e) {
        errors[w] = e.what();
      }
    });
  }
  for (auto& t : pool) t.join();
  for (const auto& e : errors) {
    if (!e.empty()) throw Error(e);
  }
  // Frame files are f<number>.ppm with POV-Ray's zero padding.
  std::map<int, std::string> frames;
  for (const auto& f : tmp.files()) {
    if (f.size() > 5 && f[0] == 'f' && f.compare(f.size() - 4, 4, ".ppm") == 0) {
      frames[std::atoi(f.substr(1, f.size() - 5).c_str())] = tmp.path() + "/" + f;
    }
  }
  render.done(std::to_string(views) + " views x 2 passes, " + std::to_string(params.size) + "x" +
              std::to_string(params.size) + " pixels, " + std::to_string(workers) + " processes");

  common::log::Phase decode("decode");
  ScanColumns cols;
  for (int k = 0; k < views; ++k) {
    if (!frames.count(2 * k) || !frames.count(2 * k + 1)) {
      throw Error("POV-Ray wrote no image for view " + std::to_string(k));
    }
    const Image16 coords = parse_ppm(common::read_file(frames[2 * k]), frames[2 * k]);
    const Image16 labels = parse_ppm(common::read_file(frames[2 * k + 1]), frames[2 * k + 1]);
    if (coords.width != params.size || labels.width != params.size) {
      throw Error("POV-Ray image of view " + std::to_string(k) + " has the wrong size");
    }
    decode_view(coords, labels, enc, placement, params, view_direction(scene.views[k], params.pose),
                k, &cols);
  }
  formats::PointCloud cloud;
  const std::size_t n = cols.points.size();
  cloud.resize(n);
  const char* names[] = {"x", "y", "z", "sensor_x", "sensor_y", "sensor_z"};
  for (int a = 0; a < 6; ++a) {
    auto& c = cloud.add(names[a], formats::kFloat32);
    for (std::size_t i = 0; i < n; ++i) c[i] = a < 3 ? cols.points[i][a] : cols.sensor[i][a - 3];
  }
  auto& vi = cloud.add("view_idx", formats::kInt32);
  auto& lb = cloud.add("label", formats::kUint32);
  for (std::size_t i = 0; i < n; ++i) {
    vi[i] = cols.view_idx[i];
    lb[i] = cols.label[i];
  }
  decode.done(std::to_string(n) + " points in the crop box");
  return cloud;
}

std::string render_picture(const Model& model, const SceneRecipe* scene, int view_idx,
                           const Params& params) {
  TempDir tmp;
  const auto [lo, hi] = model_extent(model, params, tmp);
  const Placement placement = place(lo, hi, params.pose);
  std::vector<View> views = {View{0, 75 * M_PI / 180}};
  std::vector<Disc> foliage;
  if (scene != nullptr) {
    if (view_idx < 0 || view_idx >= static_cast<int>(scene->views.size())) {
      throw common::UsageError("--view " + std::to_string(view_idx) + ": the scene has " +
                               std::to_string(scene->views.size()) + " views");
    }
    views = {scene->views[view_idx]};
    foliage = make_foliage(*scene, params.pose, placement.top, params.seed);
  }
  common::write_file_atomic(tmp.path() + "/picture.pov",
                            scene_pov(model, placement, encoding_for(placement, params), views,
                                      foliage, params, scene != nullptr ? 1 : 2));
  auto args = common_args(model);
  const std::string size = std::to_string(params.size);
  args.insert(args.end(), {"+W" + size, "+H" + size, "+A0.05", "+R3", "+FN8", "+Ipicture.pov",
                           "+Opicture.png", "+WT" + std::to_string(std::max(1, params.threads))});
  run_povray(params, tmp.path(), args, "picture.log");
  return common::read_file(tmp.path() + "/picture.png");
}

}  // namespace canopy::rangetrace
