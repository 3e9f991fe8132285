// The flow of `caustica render`: signals, rendering each frame with its progress, and the paths
// under mpirun; planning is in app/render_plan.cpp, writing in app/render_output.cpp.
#include "app/render_command.h"

#include "app/animation.h"
#include "app/progress_bar.h"
#include "app/render_interrupt.h"
#include "app/render_output.h"
#include "app/render_plan.h"
#include "core/io/atomic_file.h"
#include "core/render/accumulation_state.h"
#include "core/render/random.h"
#include "core/render/render_session.h"
#include "core/render/cluster.h"
#include "core/util/printable_text.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <new>
#include <optional>
#include <random>

#include <tbb/info.h>
#include <stdexcept>
#include <thread>
#include <unistd.h>

namespace caustica {

std::atomic<bool> interrupted{false};

namespace {

/// The first Ctrl-C or SIGTERM asks every stage to stop (within a second); a second one leaves at
/// once, removing the temporary of an image being written (PNG, EXR or PFM) so that nothing
/// partial stays behind.
extern "C" void on_interrupt(int) {
    if (!interrupted.exchange(true)) return;
    remove_output_temporaries_from_signal_handler();
    ::_exit(exit_interrupted);
}

/// --resume: the accumulation saved beside a frame's image (docs/OUTPUT.md, "Resuming an
/// accumulation"), continued when there is one and kept up to date while rendering.
struct StateSaving {
    std::string path;                          // IMAGE.caustica-state
    bool inside_current_folder = false;        // a script's name: written as its image is
    std::optional<AccumulationState> start;    // the saved accumulation to continue
    double next_save = 0.0;                    // steady-clock seconds of the next periodic save
    bool requested = false;                    // a snapshot is on its way
};

/// At least this long between two periodic saves of a running accumulation, and at least ten
/// times what the last save took (a large image's state is large): a crash loses little, the
/// saves take little.
constexpr double state_save_interval = 30.0;

double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The saved accumulation of `frame` to continue, if its file exists: refused (InputError naming
/// the file) when it is damaged or belongs to another job, before anything is rendered.
StateSaving state_saving_for(const AnimationFrame& frame) {
    StateSaving saving;
    saving.path = accumulation_state_path(frame.path);
    saving.inside_current_folder = frame.named_by_script;
    saving.next_save = steady_seconds() + state_save_interval;
    std::error_code ec;
    if (!std::filesystem::exists(saving.path, ec)) return saving;
    const AccumulationKey key = accumulation_key(frame.job);
    AccumulationState state = read_accumulation_state(saving.path, key.width, key.height);
    if (const std::string mismatch = accumulation_mismatch(state.key, key); !mismatch.empty())
        throw InputError(saving.path + ": cannot continue this accumulation: " + mismatch +
                         " (remove the file to start again, or write the image under another name)");
    if (!frame.job.options.silent)
        std::fprintf(stderr, "continuing the accumulation in %s (%d passes)\n", printable_text(saving.path).c_str(),
                     state.next_pass);
    saving.start = std::move(state);
    return saving;
}

/// Writes a state, and schedules the next periodic save by how long this one took.
void write_state(const AccumulationState& state, StateSaving& saving) {
    const double t0 = steady_seconds();
    write_accumulation_state(saving.path, state, saving.inside_current_folder);
    const double now = steady_seconds();
    saving.next_save = now + std::max(state_save_interval, 10.0 * (now - t0));
}

/// While rendering: asks for a snapshot when a save is due, and writes it once made (a failed
/// write is a warning: the render goes on, and the save at its end says it again).
void save_periodically(RenderSession& session, StateSaving& saving, bool quiet) {
    AccumulationState state;
    if (saving.requested && session.take_accumulation_snapshot(state)) {
        saving.requested = false;
        try {
            write_state(state, saving);
        } catch (const std::exception& e) {
            saving.next_save = steady_seconds() + state_save_interval;
            if (!quiet) std::fprintf(stderr, "\nwarning: %s\n", printable_text(e.what()).c_str());
        }
    } else if (!saving.requested && steady_seconds() >= saving.next_save) {
        session.request_accumulation_snapshot();
        saving.requested = true;
    }
}

/// Renders one job to completion (or interruption), showing its progress when `show`; with
/// `saving` (--resume) continues its saved accumulation and saves it periodically. Returns
/// exit_ok or exit_interrupted; rethrows the session's errors.
int render_frame(RenderSession& session, const RenderJob& job, const std::string& path, bool show,
                 StateSaving* saving = nullptr) {
    const Options& o = job.options;
    session.set_job(job);
    if (o.verbose && !o.silent)
        std::fprintf(stderr, "%s: rendering %s (%d x %d)\n", printable_text(job.where.str()).c_str(),
                     printable_text(path).c_str(), o.resolution_override ? o.resolution_override : job.width,
                     o.resolution_override ? o.resolution_override : job.height);
    if (saving && saving->start) {
        AccumulationState start = std::move(*saving->start);
        saving->start.reset();
        session.start_from(std::move(start));
    } else {
        session.start();
    }
    ProgressBar bar(show && !o.silent);
    for (;;) {
        const SessionProgress p = session.progress();
        if (!p.running) break;
        if (interrupted) session.cancel();
        if (saving && !interrupted) save_periodically(session, *saving, o.silent);
        if (p.accumulating) {
            // Passes have no fixed total: the nearest stopping rule gives the fraction.
            double fraction = 0.0;
            if (o.pass_limit() > 0) fraction = std::max(fraction, double(p.passes_done) / o.pass_limit());
            if (o.time_limit > 0.0) fraction = std::max(fraction, p.elapsed_seconds / o.time_limit);
            if (o.target_error > 0.0 && p.error.known)
                fraction = std::max(fraction, std::min(1.0, o.target_error / p.error.relative));
            char status[160];
            if (p.error.known)
                std::snprintf(status, sizeof status, "pass %d, %.3g photons, estimated error %.1f%%", p.passes_done,
                              double(p.photons_emitted), 100.0 * p.error.relative);
            else
                std::snprintf(status, sizeof status, "pass %d, %.3g photons", p.passes_done, double(p.photons_emitted));
            bar.update(std::min(1.0, fraction), p.elapsed_seconds, status);
        } else {
            bar.update(p.tiles_total ? double(p.tiles_done) / double(p.tiles_total) : 0.0, p.elapsed_seconds, p.stage);
        }
        session.wait_for_end(0.05);  // the bar and the interrupt every 50 ms, the end at once
    }
    bar.finish();
    const bool complete = session.wait();  // rethrows scene errors found while preparing
    if (show && !o.silent)
        for (const std::string& w : session.warnings()) std::fprintf(stderr, "warning: %s\n", printable_text(w).c_str());
    return complete && !interrupted ? exit_ok : exit_interrupted;
}

/// --resume: saves the accumulation the render left (interrupted or not); returns its passes, or
/// -1 when there was none to save (an interruption before the first pass: the file is kept).
int save_final_state(const RenderSession& session, StateSaving& saving) {
    AccumulationState state;
    if (!session.accumulation_state(state)) return -1;
    write_state(state, saving);
    return state.next_pass;
}

/// Renders one frame and writes its image; with `resume`, continues and saves its accumulation.
int render_job(RenderSession& session, const AnimationFrame& frame, const std::string& scene_path, const std::string& label,
               bool resume) {
    std::optional<StateSaving> saving;
    if (resume) saving = state_saving_for(frame);
    const bool quiet = frame.job.options.silent;
    if (render_frame(session, frame.job, frame.path, true, saving ? &*saving : nullptr) != exit_ok) {
        if (!quiet) std::fprintf(stderr, "caustica: interrupted; %s not written\n", printable_text(frame.path).c_str());
        if (saving)
            if (const int passes = save_final_state(session, *saving); passes >= 0 && !quiet)
                std::fprintf(stderr, "caustica: its accumulation (%d passes) is saved in %s; the same command continues it\n",
                             passes, printable_text(saving->path).c_str());
        return exit_interrupted;
    }
    int code = exit_ok;
    try {
        code = write_frame(frame, scene_path, label, session.image(), session.stats(), nullptr, &session.layers());
    } catch (...) {
        // The image could not be written: the accumulation is kept if it can be, for the next run.
        if (saving) try {
                save_final_state(session, *saving);
            } catch (...) {
            }
        throw;
    }
    if (saving) save_final_state(session, *saving);  // also when Ctrl-C stopped the image's write
    return code;
}

/// Rank 0 tells the user what stopped every rank (an interruption once: `said` when it was);
/// every rank exits with its code.
int report(const RankFailure& failure, const Cluster& cluster, bool said = false) {
    if (cluster.rank() == 0) {
        if (failure.exit_code == exit_interrupted) {
            if (!said) std::fprintf(stderr, "caustica: interrupted; nothing more written\n");
        } else if (failure.rank == 0) {
            std::fprintf(stderr, "caustica: %s\n", printable_text(failure.message).c_str());
        } else {
            std::fprintf(stderr, "caustica: rank %d of %d: %s\n", failure.rank, cluster.size(),
                         printable_text(failure.message).c_str());
        }
    }
    return failure.exit_code;
}

/// A rendered frame as bytes for rank 0, and back: the image, what its metadata reports and
/// what -t/-S print about it.
Cluster::Bytes frame_bytes(const Image& image, const RenderStats& stats, const std::string& text) {
    Cluster::Bytes bytes;
    auto put = [&](const void* p, std::size_t n) {
        bytes.insert(bytes.end(), static_cast<const std::uint8_t*>(p), static_cast<const std::uint8_t*>(p) + n);
    };
    const std::int32_t size[2] = {image.width, image.height};
    put(size, sizeof size);
    const double numbers[5] = {stats.total_seconds, static_cast<double>(stats.accumulation.passes),
                               static_cast<double>(stats.accumulation.photons_emitted), stats.accumulation.error,
                               static_cast<double>(stats.threads)};
    put(numbers, sizeof numbers);
    put(image.pixels.data(), image.pixels.size() * sizeof(glm::vec3));
    put(text.data(), text.size());
    return bytes;
}

void frame_of(const Cluster::Bytes& bytes, Image& image, RenderStats& stats, std::string& text) {
    std::int32_t size[2];
    double numbers[5];
    if (bytes.size() < sizeof size + sizeof numbers) throw std::runtime_error("a frame from another rank is truncated");
    std::memcpy(size, bytes.data(), sizeof size);
    std::memcpy(numbers, bytes.data() + sizeof size, sizeof numbers);
    const std::size_t pixels = static_cast<std::size_t>(std::max(0, size[0])) * static_cast<std::size_t>(std::max(0, size[1]));
    const std::size_t image_end = sizeof size + sizeof numbers + pixels * sizeof(glm::vec3);
    if (bytes.size() < image_end) throw std::runtime_error("a frame from another rank has the wrong size");
    image = Image(size[0], size[1]);
    std::memcpy(image.pixels.data(), bytes.data() + sizeof size + sizeof numbers, pixels * sizeof(glm::vec3));
    text.assign(bytes.begin() + static_cast<std::ptrdiff_t>(image_end), bytes.end());
    stats = RenderStats{};
    stats.total_seconds = numbers[0];
    stats.accumulation.passes = static_cast<int>(numbers[1]);
    stats.accumulation.photons_emitted = static_cast<long long>(numbers[2]);
    stats.accumulation.error = numbers[3];
    stats.threads = static_cast<int>(numbers[4]);
}

/// This rank's failure from a caught exception, with out-of-memory named as a scene error.
std::optional<RankFailure> failure_here(std::exception_ptr error, const Cluster& cluster, const AnimationFrame* frame) {
    if (!error) return std::nullopt;
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        if (frame) return failure_of(std::make_exception_ptr(out_of_memory(frame->job, frame->path)), cluster.rank());
    } catch (...) {
    }
    return failure_of(error, cluster.rank());
}

/// What every rank must render alike: each frame's job by content (computed once per gr.render:
/// a scene's meshes are hashed whole) and its camera (orbit frames differ by it alone).
std::uint64_t plan_fingerprint(const AnimationPlan& plan) {
    std::uint64_t fingerprint = plan.frames.size();
    std::map<int, std::uint64_t> by_job;
    for (const AnimationFrame& frame : plan.frames) {
        auto [it, fresh] = by_job.try_emplace(frame.job_index, 0);
        if (fresh) it->second = job_content_fingerprint(frame.job);
        fingerprint = hash_combine(fingerprint, it->second);
        const CameraDesc& c = frame.job.camera;
        for (double v : {c.eye.x, c.eye.y, c.eye.z, c.view.x, c.view.y, c.view.z, c.up.x, c.up.y, c.up.z, c.fovy_degrees})
            fingerprint = hash_double(fingerprint, v);
    }
    return fingerprint;
}

/// -j as the frames have it (0: every core the process may use).
int command_line_threads(const RenderPlan& plan) { return plan.plan.frames.front().job.options.threads; }

/// Under mpirun: the frames rendered by every rank together (a frame at a time: fewer frames than
/// ranks), or whole frames shared out in rounds of one per rank. Rank 0 writes every file.
int render_with_ranks(Cluster& cluster, RenderSession& session, const RenderPlan& plan) {
    const std::vector<AnimationFrame>& frames = plan.plan.frames;
    const bool root = cluster.rank() == 0;
    const int ranks = cluster.size();
    auto label = [&](const AnimationFrame& f) { return plan.numbered ? frame_label(f) : std::string(); };
    if (static_cast<int>(frames.size()) <= ranks) {
        session.set_cluster(&cluster);
        for (const AnimationFrame& frame : frames) {
            // Every rank renders; once every rank says it finished, rank 0 writes (an interruption
            // anywhere before that writes nothing).
            std::exception_ptr error;
            int code = exit_ok;
            try {
                code = render_frame(session, frame.job, frame.path, root);
            } catch (...) {
                error = std::current_exception();
            }
            std::optional<RankFailure> mine = failure_here(error, cluster, &frame);
            if (!mine && code != exit_ok) mine = RankFailure{cluster.rank(), code, "interrupted"};
            if (const std::optional<RankFailure> failure = cluster.agree(mine)) {
                if (root && failure->exit_code == exit_interrupted && !frame.job.options.silent)
                    std::fprintf(stderr, "caustica: interrupted; %s not written\n", printable_text(frame.path).c_str());
                return report(*failure, cluster, true);
            }
            mine.reset();
            if (root) {
                try {
                    code = write_frame(frame, plan.parsed.scene, label(frame), session.image(), session.stats(), nullptr,
                                       &session.layers());
                } catch (...) {
                    mine = failure_here(std::current_exception(), cluster, nullptr);
                }
                if (!mine && code != exit_ok) mine = RankFailure{0, code, "interrupted"};
            }
            if (const std::optional<RankFailure> failure = cluster.agree(mine)) return report(*failure, cluster, true);
        }
        return exit_ok;
    }
    // More frames than ranks: each renders whole frames alone, rank k frames k, k + K, ...
    session.set_cluster(nullptr);
    const std::size_t count = frames.size();
    for (std::size_t round = 0; round * static_cast<std::size_t>(ranks) < count; ++round) {
        const std::size_t mine_index = round * static_cast<std::size_t>(ranks) + static_cast<std::size_t>(cluster.rank());
        Cluster::Bytes result;
        std::exception_ptr error;
        int code = exit_ok;
        if (mine_index < count) {
            const AnimationFrame& frame = frames[mine_index];
            try {
                code = render_frame(session, frame.job, frame.path, root);
                const RenderStats stats = session.stats();
                if (code == exit_ok)
                    result = frame_bytes(session.image(), stats, stats_text(stats, frame.job.options.timing, frame.job.options.stats));
            } catch (...) {
                error = std::current_exception();
            }
        }
        std::optional<RankFailure> mine = failure_here(error, cluster, mine_index < count ? &frames[mine_index] : nullptr);
        if (!mine && code != exit_ok) mine = RankFailure{cluster.rank(), code, "interrupted"};
        if (const std::optional<RankFailure> failure = cluster.agree(mine)) return report(*failure, cluster);
        const std::vector<Cluster::Bytes> results = cluster.gather(result);
        mine.reset();
        code = exit_ok;
        if (root) {
            try {
                for (std::size_t r = 0; r < results.size() && round * ranks + r < count && code == exit_ok; ++r) {
                    const AnimationFrame& frame = frames[round * static_cast<std::size_t>(ranks) + r];
                    Image image;
                    RenderStats stats;
                    std::string text;
                    frame_of(results[r], image, stats, text);
                    code = write_frame(frame, plan.parsed.scene, label(frame), image, stats, &text);
                }
            } catch (...) {
                mine = failure_here(std::current_exception(), cluster, nullptr);
            }
            if (!mine && code != exit_ok) mine = RankFailure{0, code, "interrupted"};
        }
        if (const std::optional<RankFailure> failure = cluster.agree(mine)) return report(*failure, cluster);
    }
    return exit_ok;
}

}  // namespace

std::string render_help() {
    return "usage: caustica render [options] SCENE.lua [-o OUT.png|OUT.exr|OUT.pfm]\n"
           "\n"
           "Runs the scene script and renders every gr.render it calls. Without -o each render\n"
           "writes the file the script names, relative to the current folder; with -o a single\n"
           "render writes OUT.png and several write OUT-1.png, OUT-2.png, ...\n"
           "Animations (docs/ANIMATION.md; command line only):\n"
           "  --frames A:B       render frames A to B only (numbered from 1; --frames N: frame N);\n"
           "                     without --orbit-frames the frames are the script's gr.render calls\n"
           "  --orbit-frames N   N frames of the first gr.render, its camera turned 360 degrees about\n"
           "                     its up vector around the first surface on its view axis; written as\n"
           "                     OUT-0001.png ... (or the script's name with -0001 before the extension)\n"
           "The extension picks the format: .png (8-bit; --srgb, --tonemap), .exr (OpenEXR, linear\n"
           "and unclamped, half or --exr-pixel float, parameters in the header) or .pfm (linear float).\n"
           "--exposure scales every format. docs/OUTPUT.md has the details.\n"
           "  --resume           (command line only; progressive accumulation, not under mpirun)\n"
           "                     continue the accumulation saved in OUT.caustica-state beside the\n"
           "                     image, if any (refused if it belongs to another scene, camera, size\n"
           "                     or options), and keep it saved there: every 30 s, at the end and on\n"
           "                     Ctrl-C; --passes, --time and --target-error count from its start\n"
           "--layers (OUT.exr only) adds layers to the EXR: direct.R/G/B, indirect.*, caustic.*,\n"
           "background.* (together the image), albedo.R/G/B and normal.X/Y/Z (docs/OUTPUT.md, Layers);\n"
           "progressive passes accumulate them with the image. --show-layer NAME renders one as the image.\n"
           "The script runs sandboxed: it reads only regular files under its own folder, and\n"
           "--allow-read DIR (repeatable, command line only) lets it read under DIR too.\n"
           "Script names for gr.render are relative to the current folder, without '..', and\n"
           "must lead inside it with every symlink followed.\n"
           "Options may also be set in the scene with gr.option('--flag ...'); the command line wins.\n"
           "Exit codes: 0 success, 1 output could not be written (a missing or unwritable folder, found\n"
           "before or after rendering), 2 scene or usage error (a scene that needs more memory than\n"
           "there is included), 130 interrupted (nothing written).\n" +
           options_help();
}

int run_render_command(const std::vector<std::string>& args, Cluster* cluster) {
    if (cluster && cluster->size() <= 1) cluster = nullptr;
    const bool root = !cluster || cluster->rank() == 0;
    std::signal(SIGINT, on_interrupt);
    std::signal(SIGTERM, on_interrupt);
    RenderSession session;
    session.set_photon_lookups(false);  // nothing looks photons up after a batch render
    RenderPlan plan;
    if (!cluster) {
        const int early = plan_render(args, session, true, plan);
        if (early >= 0) return early;
        for (const AnimationFrame& frame : plan.plan.frames) {
            int code = exit_ok;
            try {
                code = render_job(session, frame, plan.parsed.scene, plan.numbered ? frame_label(frame) : "",
                                  plan.parsed.resume);
            } catch (const std::bad_alloc&) {
                throw out_of_memory(frame.job, frame.path);
            }
            if (code != exit_ok) return code;
        }
        return exit_ok;
    }
    // Under mpirun every rank plans the same frames from the same script; a rank that cannot
    // stops them all, with its message.
    int early = -1;
    std::exception_ptr error;
    try {
        early = plan_render(args, session, root, plan);
        if (early < 0)
            for (const AnimationFrame& frame : plan.plan.frames) {
                // The ranks gather the layers with the tiles of one image pass, not with the sums
                // of an accumulation or with whole frames.
                if (frame.job.options.layers && frame.job.options.accumulates())
                    throw InputError("--layers under mpirun: the ranks of a progressive accumulation do not add "
                                     "up their layers; run it without mpirun, or drop --passes, --time and "
                                     "--target-error");
                if (frame.job.options.layers && plan.plan.frames.size() > static_cast<std::size_t>(cluster->size()))
                    throw InputError("--layers under mpirun: with more frames than processes each renders whole "
                                     "frames, whose layers are not sent; use at least as many processes as frames");
            }
    } catch (...) {
        error = std::current_exception();
    }
    std::optional<RankFailure> mine = failure_here(error, *cluster, nullptr);
    if (!mine && early == exit_interrupted) mine = RankFailure{cluster->rank(), exit_interrupted, "interrupted"};
    if (const std::optional<RankFailure> failure = cluster->agree(mine)) return report(*failure, *cluster);
    // --help ends every rank, which must all have been given it (mpirun's MPMD form may not).
    const long long ending = cluster->all_sum(early >= 0 ? 1 : 0);
    if (ending == cluster->size()) return early;
    mine.reset();
    if (ending > 0 && early >= 0)
        mine = RankFailure{cluster->rank(), exit_usage, "this rank was given --help while the others render: give every rank the same arguments"};
    else if (plan.parsed.resume)  // the ranks' sums meet only at the end of a frame (docs/OUTPUT.md)
        mine = RankFailure{cluster->rank(), exit_usage,
                           "--resume works in a single process, not under mpirun: run the accumulation to resume "
                           "without mpirun"};
    if (const std::optional<RankFailure> failure = cluster->agree(mine)) return report(*failure, *cluster);
    // Every rank must render the same jobs: the same binary on the same files with the same
    // options. A rank that loaded something else (a node with other files) says so.
    const std::uint64_t fingerprint = plan_fingerprint(plan.plan);
    Cluster::Bytes first_fingerprint(sizeof fingerprint);
    std::memcpy(first_fingerprint.data(), &fingerprint, sizeof fingerprint);
    cluster->broadcast(first_fingerprint, 0);
    std::uint64_t rank0_fingerprint = 0;
    std::memcpy(&rank0_fingerprint, first_fingerprint.data(), sizeof rank0_fingerprint);
    mine.reset();
    if (rank0_fingerprint != fingerprint)
        mine = RankFailure{cluster->rank(), exit_usage,
                           plan.parsed.scene + ": this rank's scene, options or files differ from rank 0's (every rank "
                           "must run the same caustica on the same files with the same options)"};
    if (const std::optional<RankFailure> failure = cluster->agree(mine)) return report(*failure, *cluster);
    // mpirun binds each rank to cores (to one core when it starts two or fewer): say so when a
    // rank gets fewer cores than its share of this machine.
    if (root && command_line_threads(plan) == 0 && !plan.plan.frames.front().job.options.silent) {
        const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
        const int here = local ? std::max(1, std::atoi(local)) : 1;
        const int usable = tbb::info::default_concurrency();
        const unsigned machine = std::thread::hardware_concurrency();
        if (machine > 0 && static_cast<unsigned>(usable * here) < machine)
            std::fprintf(stderr,
                         "warning: each rank renders on %d of this machine's %u cores (mpirun binds ranks to cores; "
                         "with fewer ranks than cores add --bind-to none, or --map-by node:PE=N)\n",
                         usable, machine);
    }
    // The ranks share their random streams: without --reproducible rank 0 draws the seed (the
    // images' options then record it: the render can be repeated).
    Cluster::Bytes seed(sizeof(std::uint64_t));
    if (root) {
        const std::uint64_t drawn = (static_cast<std::uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();
        std::memcpy(seed.data(), &drawn, sizeof drawn);
    }
    cluster->broadcast(seed, 0);
    std::uint64_t shared_seed = 0;
    std::memcpy(&shared_seed, seed.data(), sizeof shared_seed);
    for (AnimationFrame& frame : plan.plan.frames) {
        Options& o = frame.job.options;
        if (o.reproducible) continue;
        o.reproducible = true;
        o.seed = static_cast<long long>(shared_seed & 0x7fffffffffffULL);
    }
    return render_with_ranks(*cluster, session, plan);
}

}  // namespace caustica
