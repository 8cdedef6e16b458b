// warpfem warp-image: warp a PNG from a source to a target polygon.

#include <filesystem>

#include "apps/command_line.hpp"
#include "apps/commands.hpp"
#include "apps/image_warp.hpp"
#include "core/collective_error.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "io/png_image.hpp"
#include "io/run_config.hpp"
#include "mapping/make_map.hpp"

namespace warpfem::apps {

int warp_image_command(const std::vector<std::string>& args) {
  const char* usage = "usage: warpfem warp-image --config warp.json [--input in.png] [--output out.png]";
  std::string config_path, input, output;
  for (std::size_t i = 0; i < args.size(); ++i) {
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size())
        throw Error(args[i] + " needs a value", {.file = "", .key_path = "", .hint = usage});
      return args[++i];
    };
    if (args[i] == "--config")
      config_path = value();
    else if (args[i] == "--input")
      input = value();
    else if (args[i] == "--output")
      output = value();
    else
      check_flag(args[i], {"--config", "--input", "--output"}, usage);
  }
  if (config_path.empty()) throw Error("missing --config", {.file = "", .key_path = "", .hint = usage});
  const nlohmann::json json = io::ConfigNode::parse_file(config_path);
  const io::ConfigNode root(json, config_path);
  log::set_level(log::parse_level(io::parse_verbosity(root)));
  const mapping::MapSpec spec = io::parse_required_map(root);
  const io::ConfigNode image = root.child("image");
  if (input.empty()) {
    input = image.get_string("input", "");
    // Like polygon files, an input named in the config is relative to the config's directory.
    if (!input.empty() && std::filesystem::path(input).is_relative())
      input = (std::filesystem::path(config_path).parent_path() / input).string();
  } else {
    image.get_string("input", "");
  }
  if (output.empty())
    output = io::config_relative_path(config_path, image.get_string("output", "output/warped.png"));
  else
    image.get_string("output", "");
  std::array<std::uint8_t, 4> background{255, 255, 255, 0};
  const std::vector<double> bg = image.get_doubles("background");
  if (!bg.empty()) {
    if (bg.size() != 4) throw image.error("background", "expected [r, g, b, a] with values 0..255");
    for (int c = 0; c < 4; ++c) {
      if (bg[c] < 0 || bg[c] > 255)
        throw image.error("background", "expected [r, g, b, a] with values 0..255");
      background[c] = static_cast<std::uint8_t>(bg[c]);
    }
  }
  const int width = static_cast<int>(image.get_int("width", 0, 0, 65536));
  const int height = static_cast<int>(image.get_int("height", 0, 0, 65536));
  image.finish();
  const io::SizeLimits limits = io::parse_limits(root);
  root.finish();
  io::check_map_size(root, spec, limits);
  if (input.empty())
    throw Error("no input image", {.file = config_path,
                                   .key_path = "/image/input",
                                   .hint = "add \"input\": \"picture.png\" or pass --input"});
  if (spec.type == "identity")
    throw Error("warp-image needs a target polygon",
                {.file = config_path, .key_path = "/map/type", .hint = "use \"composite_mean_value\""});

  Stopwatch watch;
  const mapping::MapPtr<2> map = mapping::make_map(spec);  // errors name spec.origin = the config file
  log::info("map: ", map->describe(), " (", format_seconds(watch.seconds()), ")");
  const io::Image in = io::read_png(input);
  io::Image out;
  out.width = width > 0 ? width : in.width;
  out.height = height > 0 ? height : in.height;
  if (static_cast<std::uint64_t>(out.width) * static_cast<std::uint64_t>(out.height) > io::kMaxImagePixels)
    throw Error(
        "an output of " + std::to_string(out.width) + " x " + std::to_string(out.height) +
            " pixels is more than the limit of " + std::to_string(io::kMaxImagePixels),
        {.file = config_path, .key_path = "/image/width", .hint = "choose a smaller width and height"});
  watch.reset();
  const WarpReport r = warp_image(in, *map, *spec.source, *spec.target, out, background);
  log::info("warped ", r.pixels, " pixels by inverse mapping (", format_seconds(watch.seconds()),
            "), max |f(x) - y| = ", r.max_residual);
  if (r.unconverged > 0) log::warning(r.unconverged, " pixels did not converge to the tolerance");
  warpfem::run_collectively(MPI_COMM_WORLD, [&] {
    if (Environment::rank() == 0) io::write_png(output, out);
  });
  log::info("wrote ", output);
  return 0;
}

}  // namespace warpfem::apps
