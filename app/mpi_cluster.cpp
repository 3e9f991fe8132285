#include "app/mpi_cluster.h"
#include "core/util/printable_text.h"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

namespace caustica {
namespace {

// share_work's messages (on their own communicator: never confused with a collective's).
constexpr int tag_request = 1;  // a worker asks for a batch
constexpr int tag_result = 2;   // a worker returns a batch's result (and asks for another)
constexpr int tag_batch = 3;    // rank 0 gives a batch: two ints, [first, last)
constexpr int tag_stop = 4;     // rank 0 has no batch left
constexpr int tag_gather = 5;   // gather(): a rank's size, then its bytes

/// Collectives move at most this many bytes (or elements) in one call: MPI counts are ints.
constexpr std::size_t max_chunk = std::size_t(1) << 28;

void check(int code, const char* what) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw std::runtime_error(std::string("MPI: ") + what + " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

/// A collective that cannot finish on this rank (an MPI error, no memory for its buffers) leaves
/// the other ranks inside it, where no agreement can reach them: say why and end every rank.
template <typename Body>
auto guarded(int rank, int size, const char* what, Body&& body) -> decltype(body()) {
    try {
        return body();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "caustica: rank %d of %d: %s: %s\n", rank, size, what, printable_text(e.what()).c_str());
    }
    abort_mpi(1);
}

class MpiCluster final : public Cluster {
public:
    MpiCluster() {
        int provided = 0;
        check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
        if (provided < MPI_THREAD_SERIALIZED) {
            MPI_Finalize();
            throw std::runtime_error("MPI: this MPI library cannot be called from the render thread (needs "
                                     "MPI_THREAD_SERIALIZED)");
        }
        // Errors come back as codes (and exceptions), not as an abort without a message.
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
        check(MPI_Comm_dup(MPI_COMM_WORLD, &collectives_), "MPI_Comm_dup");
        check(MPI_Comm_dup(MPI_COMM_WORLD, &work_), "MPI_Comm_dup");
        MPI_Comm_rank(collectives_, &rank_);
        MPI_Comm_size(collectives_, &size_);
    }

    ~MpiCluster() override {
        MPI_Comm_free(&work_);
        MPI_Comm_free(&collectives_);
        MPI_Finalize();
    }

    int rank() const override { return rank_; }
    int size() const override { return size_; }

    std::optional<RankFailure> agree_unguarded(const std::optional<RankFailure>& mine) {
        const int candidate = mine ? rank_ : size_;
        int first = size_;
        check(MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, collectives_), "MPI_Allreduce");
        if (first == size_) return std::nullopt;
        // The lowest failing rank sends its failure: the rank it names (a failure agreed on
        // before, passed on, names the rank that had it), the exit code, the message.
        Bytes message;
        std::int32_t header[2] = {first, 1};
        if (rank_ == first) {
            header[0] = mine->rank;
            header[1] = mine->exit_code;
            message.resize(sizeof header + mine->message.size());
            std::memcpy(message.data(), header, sizeof header);
            std::copy(mine->message.begin(), mine->message.end(), message.begin() + sizeof header);
        }
        broadcast(message, first);
        if (message.size() >= sizeof header) std::memcpy(header, message.data(), sizeof header);
        RankFailure failure;
        failure.rank = header[0];
        failure.exit_code = header[1];
        failure.message.assign(message.begin() + static_cast<std::ptrdiff_t>(std::min(message.size(), sizeof header)),
                               message.end());
        return failure;
    }

    void broadcast_unguarded(Bytes& bytes, int root) {
        std::uint64_t n = bytes.size();
        check(MPI_Bcast(&n, 1, MPI_UINT64_T, root, collectives_), "MPI_Bcast");
        if (rank_ != root) bytes.resize(static_cast<std::size_t>(n));
        for (std::size_t at = 0; at < bytes.size(); at += max_chunk) {
            const int count = static_cast<int>(std::min(max_chunk, bytes.size() - at));
            check(MPI_Bcast(bytes.data() + at, count, MPI_BYTE, root, collectives_), "MPI_Bcast");
        }
    }

    std::vector<Bytes> all_gather_unguarded(const Bytes& mine) {
        const std::size_t ranks = static_cast<std::size_t>(size_);
        std::vector<std::uint64_t> sizes(ranks);
        std::uint64_t my_size = mine.size();
        check(MPI_Allgather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, collectives_), "MPI_Allgather");
        std::vector<Bytes> all(ranks);
        for (std::size_t r = 0; r < ranks; ++r) all[r].resize(static_cast<std::size_t>(sizes[r]));
        // In rounds of at most `chunk` bytes per rank, so that every count and offset fits an int.
        const std::size_t chunk = std::max<std::size_t>(1, std::min(max_chunk, static_cast<std::size_t>(INT_MAX) / ranks));
        std::vector<int> counts(ranks), offsets(ranks);
        Bytes round;
        for (std::size_t at = 0;; at += chunk) {
            std::size_t total = 0;
            for (std::size_t r = 0; r < ranks; ++r) {
                counts[r] = static_cast<int>(sizes[r] > at ? std::min<std::size_t>(chunk, sizes[r] - at) : 0);
                offsets[r] = static_cast<int>(total);
                total += static_cast<std::size_t>(counts[r]);
            }
            if (total == 0) break;
            round.resize(total);
            const std::size_t mine_count = static_cast<std::size_t>(counts[static_cast<std::size_t>(rank_)]);
            check(MPI_Allgatherv(mine_count ? mine.data() + at : nullptr, static_cast<int>(mine_count), MPI_BYTE,
                                 round.data(), counts.data(), offsets.data(), MPI_BYTE, collectives_),
                  "MPI_Allgatherv");
            for (std::size_t r = 0; r < ranks; ++r)
                if (counts[r] > 0)
                    std::memcpy(all[r].data() + at, round.data() + offsets[r], static_cast<std::size_t>(counts[r]));
        }
        return all;
    }

    std::vector<Bytes> gather_unguarded(const Bytes& mine) {
        // Point to point on the work communicator (no share_work is running): each rank's size,
        // then its bytes in chunks, received by rank 0 in rank order.
        std::vector<Bytes> all;
        if (rank_ != 0) {
            const std::uint64_t n = mine.size();
            check(MPI_Send(&n, 1, MPI_UINT64_T, 0, tag_gather, work_), "MPI_Send");
            for (std::size_t at = 0; at < mine.size(); at += max_chunk)
                check(MPI_Send(mine.data() + at, static_cast<int>(std::min(max_chunk, mine.size() - at)), MPI_BYTE, 0,
                               tag_gather, work_),
                      "MPI_Send");
            return all;
        }
        all.resize(static_cast<std::size_t>(size_));
        all[0] = mine;
        for (int r = 1; r < size_; ++r) {
            std::uint64_t n = 0;
            check(MPI_Recv(&n, 1, MPI_UINT64_T, r, tag_gather, work_, MPI_STATUS_IGNORE), "MPI_Recv");
            Bytes& bytes = all[static_cast<std::size_t>(r)];
            bytes.resize(static_cast<std::size_t>(n));
            for (std::size_t at = 0; at < bytes.size(); at += max_chunk)
                check(MPI_Recv(bytes.data() + at, static_cast<int>(std::min(max_chunk, bytes.size() - at)), MPI_BYTE, r,
                               tag_gather, work_, MPI_STATUS_IGNORE),
                      "MPI_Recv");
        }
        return all;
    }

    void reduce_sum_unguarded(std::vector<std::int64_t>& values) {
        for (std::size_t at = 0; at < values.size(); at += max_chunk / 8) {
            const int count = static_cast<int>(std::min(max_chunk / 8, values.size() - at));
            if (rank_ == 0)
                check(MPI_Reduce(MPI_IN_PLACE, values.data() + at, count, MPI_INT64_T, MPI_SUM, 0, collectives_),
                      "MPI_Reduce");
            else
                check(MPI_Reduce(values.data() + at, nullptr, count, MPI_INT64_T, MPI_SUM, 0, collectives_),
                      "MPI_Reduce");
        }
    }

    long long all_sum_unguarded(long long value) {
        long long sum = 0;
        check(MPI_Allreduce(&value, &sum, 1, MPI_LONG_LONG, MPI_SUM, collectives_), "MPI_Allreduce");
        return sum;
    }

    double all_max_unguarded(double value) {
        double m = value;
        check(MPI_Allreduce(&value, &m, 1, MPI_DOUBLE, MPI_MAX, collectives_), "MPI_Allreduce");
        return m;
    }

    std::optional<RankFailure> agree(const std::optional<RankFailure>& mine) override {
        return guarded(rank_, size_, "MPI agree", [&] { return agree_unguarded(mine); });
    }

    void broadcast(Bytes& bytes, int root) override {
        return guarded(rank_, size_, "MPI broadcast", [&] { return broadcast_unguarded(bytes, root); });
    }

    std::vector<Bytes> all_gather(const Bytes& mine) override {
        return guarded(rank_, size_, "MPI all_gather", [&] { return all_gather_unguarded(mine); });
    }

    std::vector<Bytes> gather(const Bytes& mine) override {
        return guarded(rank_, size_, "MPI gather", [&] { return gather_unguarded(mine); });
    }

    void reduce_sum(std::vector<std::int64_t>& values) override {
        return guarded(rank_, size_, "MPI reduce_sum", [&] { return reduce_sum_unguarded(values); });
    }

    long long all_sum(long long value) override {
        return guarded(rank_, size_, "MPI all_sum", [&] { return all_sum_unguarded(value); });
    }

    double all_max(double value) override {
        return guarded(rank_, size_, "MPI all_max", [&] { return all_max_unguarded(value); });
    }

    std::optional<RankFailure> share_work(int count, int batch, const WorkFn& work, const CollectFn& collect,
                                          const std::atomic<bool>* cancel) override {
        batch = std::max(1, batch);
        std::optional<RankFailure> mine;
        // This rank's work on a batch; nothing once it failed or was interrupted.
        auto run = [&](int first, int last) -> std::optional<Bytes> {
            if (mine) return std::nullopt;
            if (cancel && cancel->load()) {
                mine = RankFailure{rank_, cluster_interrupted_code, "interrupted"};
                return std::nullopt;
            }
            try {
                return work(first, last);
            } catch (...) {
                mine = failure_of(std::current_exception(), rank_);
                return std::nullopt;
            }
        };
        auto take = [&](int first, int last, const Bytes& result) {
            try {
                collect(first, last, result);
            } catch (...) {
                if (!mine) mine = failure_of(std::current_exception(), rank_);
            }
        };
        guarded(rank_, size_, "MPI share_work", [&] {
            if (rank_ == 0)
                hand_out(count, batch, run, take);
            else
                ask_for_work(run);
        });
        return agree(mine);
    }

private:
    /// Rank 0: answers every request with the next batch (or a stop), works batches itself between
    /// requests, and collects the results. Each worker keeps two requests out: it stops after two
    /// stops.
    template <typename Run, typename Take>
    void hand_out(int count, int batch, Run& run, Take& take) {
        int next = 0;
        std::vector<int> stops(static_cast<std::size_t>(size_), 0);
        int active = size_ - 1;
        // Once a rank failed (or was interrupted) the pass is lost: no more batches for anyone,
        // so that every rank reaches the agreement at once.
        auto give_up = [&] { next = count; };
        auto reply = [&](int to) {
            if (next < count) {
                const int range[2] = {next, std::min(count, next + batch)};
                next = range[1];
                check(MPI_Send(range, 2, MPI_INT, to, tag_batch, work_), "MPI_Send");
            } else {
                check(MPI_Send(nullptr, 0, MPI_INT, to, tag_stop, work_), "MPI_Send");
                if (++stops[static_cast<std::size_t>(to)] == 2) --active;
            }
        };
        auto serve = [&](bool wait) {
            MPI_Status status;
            int arrived = 1;
            if (wait)
                check(MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, work_, &status), "MPI_Probe");
            else
                check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, work_, &arrived, &status), "MPI_Iprobe");
            if (!arrived) return false;
            int length = 0;
            MPI_Get_count(&status, MPI_BYTE, &length);
            Bytes message(static_cast<std::size_t>(length));
            check(MPI_Recv(message.data(), length, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, work_, MPI_STATUS_IGNORE),
                  "MPI_Recv");
            constexpr std::size_t header = 2 * sizeof(std::int32_t) + 1;
            if (status.MPI_TAG == tag_result && message.size() >= header) {
                if (message[2 * sizeof(std::int32_t)] != 0) {
                    std::int32_t range[2];
                    std::memcpy(range, message.data(), sizeof range);
                    take(range[0], range[1], Bytes(message.begin() + header, message.end()));
                } else {
                    give_up();
                }
            }
            reply(status.MPI_SOURCE);
            return true;
        };
        for (;;) {
            while (serve(false)) {
            }
            if (next < count) {
                const int first = next, last = std::min(count, next + batch);
                next = last;
                if (std::optional<Bytes> result = run(first, last))
                    take(first, last, *result);
                else
                    give_up();  // this rank failed or was interrupted
            } else if (active > 0) {
                serve(true);
            } else {
                break;
            }
        }
    }

    /// A worker: two requests out; each batch received is worked (or, after a failure, returned
    /// unworked) and its result sent back as the next request, until two stops came.
    template <typename Run>
    void ask_for_work(Run& run) {
        for (int i = 0; i < 2; ++i) check(MPI_Send(nullptr, 0, MPI_BYTE, 0, tag_request, work_), "MPI_Send");
        int requests = 2;
        Bytes sending;
        MPI_Request sent = MPI_REQUEST_NULL;
        while (requests > 0) {
            MPI_Status status;
            check(MPI_Probe(0, MPI_ANY_TAG, work_, &status), "MPI_Probe");
            if (status.MPI_TAG == tag_stop) {
                check(MPI_Recv(nullptr, 0, MPI_INT, 0, tag_stop, work_, MPI_STATUS_IGNORE), "MPI_Recv");
                --requests;
                continue;
            }
            std::int32_t range[2];
            check(MPI_Recv(range, 2, MPI_INT, 0, tag_batch, work_, MPI_STATUS_IGNORE), "MPI_Recv");
            const std::optional<Bytes> result = run(range[0], range[1]);
            check(MPI_Wait(&sent, MPI_STATUS_IGNORE), "MPI_Wait");  // the last result's buffer is free again
            sending.assign(reinterpret_cast<const std::uint8_t*>(range), reinterpret_cast<const std::uint8_t*>(range) + sizeof range);
            sending.push_back(result ? 1 : 0);
            if (result) sending.insert(sending.end(), result->begin(), result->end());
            check(MPI_Isend(sending.data(), static_cast<int>(sending.size()), MPI_BYTE, 0, tag_result, work_, &sent),
                  "MPI_Isend");
        }
        check(MPI_Wait(&sent, MPI_STATUS_IGNORE), "MPI_Wait");
    }

    MPI_Comm collectives_ = MPI_COMM_NULL, work_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1;
};

}  // namespace

bool launched_by_mpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

std::unique_ptr<Cluster> start_mpi_cluster() { return std::make_unique<MpiCluster>(); }

void abort_mpi(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
}

}  // namespace caustica
