// perclod: perceptual levels of detail for building models.
#include <cstdio>  // defines __GLIBC__ on glibc
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <exception>

#include "commands.h"
#include "perclod/run_model.h"
#include "perclod/outputs.h"
#include "common.h"

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // Buffers of 1 MB and more (renders, ID buffers, perception images) are
  // mapped and unmapped, not kept in the heap when freed, so one stage's
  // freed buffers do not raise the next stage's peak
  // (BENCHMARKS.md#the-heaps-padding).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // But setting that threshold also fixes the heap's padding at 128 kB, so
  // a request of 1 MB or more found no room at the heap's top and was
  // mapped, and its pages faulted in, every time: the simplifier's per-chunk
  // quadrics (a chunk of 17k faces needs 1.4 MB) were mapped anew for each of
  // its chunks. A 64 MB pad lets such requests come from the heap and reuse
  // its pages: `perclod run configs/demo.yaml` 8.0 s instead of 10.3 s
  // (peak 377-383 MiB instead of 349), `perclod simplify` of the million-
  // triangle facade at 427 m on one core 0.56 s instead of 0.83 s in the
  // simplifier (BENCHMARKS.md#the-heaps-padding).
  mallopt(M_TOP_PAD, 64 << 20);
#endif
  CLI::App app{
      "perclod: perceptual levels of detail for detailed building models.\n"
      "Renders a model from a set of views at each viewing distance, finds the triangles\n"
      "a viewer can see, and simplifies everything else away, one LOD per distance."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("perclod ") + perclod::perclod_version());  // CMake's project version
  app.footer("Run 'perclod COMMAND --help' for the options of one command.");

  // Subcommands (one line each; keep the order of the pipeline).
  perclod::cli::register_info(app);
  perclod::cli::register_generate(app);
  perclod::cli::register_render(app);
  perclod::cli::register_perceive(app);
  perclod::cli::register_label(app);
  perclod::cli::register_simplify(app);
  perclod::cli::register_run(app);
  perclod::cli::register_judge(app);

  // An interrupted run leaves no temporaries behind (finished files stay).
  perclod::remove_temporaries_on_signals();
  // One error format (README.md#usage): "perclod: error: FILE: what" for
  // errors about a file, "perclod: error: what" for options. Exit status 1
  // for errors, 2 for usage errors (unknown option, missing argument, ...),
  // 0 for --help and --version.
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    // A bad option value (CLI11's validators and conversions) is an error;
    // everything else CLI11 refuses is a usage error.
    const bool bad_value = dynamic_cast<const CLI::ValidationError*>(&e) != nullptr ||
                           dynamic_cast<const CLI::ConversionError*>(&e) != nullptr;
    std::fprintf(stderr, "perclod: error: %s\n", e.what());
    return bad_value ? 1 : 2;
  } catch (const perclod::cli::OptionError& e) {
    std::fprintf(stderr, "perclod: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "perclod: error: %s\n", perclod::cli::error_message(e.what()).c_str());
    return 1;
  }
  return 0;
}
