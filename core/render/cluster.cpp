#include "core/render/cluster.h"

#include "core/scene/source_location.h"

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <new>

namespace caustica {

RankFailure failure_of(std::exception_ptr error, int rank) {
    RankFailure f;
    f.rank = rank;
    try {
        std::rethrow_exception(error);
    } catch (const ClusterError& e) {
        f = e.failure();
    } catch (const InputError& e) {
        f.exit_code = 2;
        f.message = e.what();
    } catch (const std::bad_alloc&) {
        f.exit_code = 2;
        f.message = "not enough memory for this scene on this machine (an allocation failed)";
    } catch (const std::exception& e) {
        f.exit_code = 1;
        f.message = e.what();
    } catch (...) {
        f.exit_code = 1;
        f.message = "unknown error";
    }
    return f;
}

void Cluster::checkpoint(std::exception_ptr mine, const std::atomic<bool>* cancel) {
    std::optional<RankFailure> failure;
    if (mine)
        failure = failure_of(mine, rank());
    else if (cancel && cancel->load())
        failure = RankFailure{rank(), cluster_interrupted_code, "interrupted"};
    checkpoint(failure);
}

void Cluster::checkpoint(const std::optional<RankFailure>& mine) {
    if (const std::optional<RankFailure> failure = agree(mine)) throw ClusterError(*failure);
}

namespace {

/// What the threads of a local cluster share: a reusable barrier and one slot per rank.
struct LocalShared {
    explicit LocalShared(int n)
        : size(n), failures(static_cast<std::size_t>(n)), bytes(static_cast<std::size_t>(n)),
          sums(static_cast<std::size_t>(n)), longs(static_cast<std::size_t>(n)), doubles(static_cast<std::size_t>(n)) {}

    void barrier() {
        std::unique_lock lock(mutex);
        const std::uint64_t generation = barrier_generation;
        if (++arrived == size) {
            arrived = 0;
            ++barrier_generation;
            wake.notify_all();
        } else {
            wake.wait(lock, [&] { return barrier_generation != generation; });
        }
    }

    const int size;
    std::mutex mutex;
    std::condition_variable wake;
    int arrived = 0;
    std::uint64_t barrier_generation = 0;
    // Slots, written by their rank before a barrier and read by all after it.
    std::vector<std::optional<RankFailure>> failures;
    std::vector<Cluster::Bytes> bytes;
    std::vector<std::vector<std::int64_t>*> sums;
    std::vector<long long> longs;
    std::vector<double> doubles;
    // share_work
    std::atomic<int> next_item{0};
    std::atomic<bool> work_failed{false};  // a rank failed: the others stop taking batches
    std::mutex collect_mutex;
    const Cluster::CollectFn* collect = nullptr;  // rank 0's
};

class LocalCluster final : public Cluster {
public:
    LocalCluster(std::shared_ptr<LocalShared> shared, int rank) : shared_(std::move(shared)), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return shared_->size; }

    std::optional<RankFailure> agree(const std::optional<RankFailure>& mine) override {
        shared_->failures[static_cast<std::size_t>(rank_)] = mine;
        shared_->barrier();
        std::optional<RankFailure> first;
        for (const std::optional<RankFailure>& f : shared_->failures)
            if (f) {
                first = f;
                break;
            }
        shared_->barrier();
        return first;
    }

    void broadcast(Bytes& bytes, int root) override {
        if (rank_ == root) shared_->bytes[static_cast<std::size_t>(root)] = bytes;
        shared_->barrier();
        if (rank_ != root) bytes = shared_->bytes[static_cast<std::size_t>(root)];
        shared_->barrier();
    }

    std::vector<Bytes> all_gather(const Bytes& mine) override {
        shared_->bytes[static_cast<std::size_t>(rank_)] = mine;
        shared_->barrier();
        std::vector<Bytes> all = shared_->bytes;
        shared_->barrier();
        return all;
    }

    std::vector<Bytes> gather(const Bytes& mine) override {
        shared_->bytes[static_cast<std::size_t>(rank_)] = mine;
        shared_->barrier();
        std::vector<Bytes> all;
        if (rank_ == 0) all = shared_->bytes;
        shared_->barrier();
        return all;
    }

    void reduce_sum(std::vector<std::int64_t>& values) override {
        shared_->sums[static_cast<std::size_t>(rank_)] = &values;
        shared_->barrier();
        if (rank_ == 0)
            for (int r = 1; r < shared_->size; ++r) {
                const std::vector<std::int64_t>& other = *shared_->sums[static_cast<std::size_t>(r)];
                if (other.size() != values.size()) {  // a bug of the caller, undefined with MPI
                    std::fprintf(stderr, "reduce_sum: rank %d has %zu values, rank 0 %zu\n", r, other.size(), values.size());
                    std::abort();
                }
                for (std::size_t i = 0; i < values.size(); ++i) values[i] += other[i];
            }
        shared_->barrier();
    }

    long long all_sum(long long value) override {
        shared_->longs[static_cast<std::size_t>(rank_)] = value;
        shared_->barrier();
        long long sum = 0;
        for (long long v : shared_->longs) sum += v;
        shared_->barrier();
        return sum;
    }

    double all_max(double value) override {
        shared_->doubles[static_cast<std::size_t>(rank_)] = value;
        shared_->barrier();
        double m = value;
        for (double v : shared_->doubles) m = v > m ? v : m;
        shared_->barrier();
        return m;
    }

    std::optional<RankFailure> share_work(int count, int batch, const WorkFn& work, const CollectFn& collect,
                                          const std::atomic<bool>* cancel) override {
        if (rank_ == 0) {
            shared_->next_item = 0;
            shared_->work_failed = false;
            shared_->collect = &collect;
        }
        shared_->barrier();
        batch = batch > 0 ? batch : 1;
        std::optional<RankFailure> mine;
        for (;;) {
            const int first = shared_->next_item.fetch_add(batch);
            if (first >= count) break;
            const int last = first + batch < count ? first + batch : count;
            if (mine || shared_->work_failed) break;  // the pass is lost: on to the agreement
            if (cancel && cancel->load()) {
                mine = RankFailure{rank_, cluster_interrupted_code, "interrupted"};
                shared_->work_failed = true;
                break;
            }
            try {
                const Bytes result = work(first, last);
                std::lock_guard lock(shared_->collect_mutex);
                (*shared_->collect)(first, last, result);
            } catch (...) {
                mine = failure_of(std::current_exception(), rank_);
                shared_->work_failed = true;
            }
        }
        return agree(mine);
    }

private:
    std::shared_ptr<LocalShared> shared_;
    int rank_;
};

}  // namespace

std::vector<std::unique_ptr<Cluster>> make_local_cluster(int size) {
    auto shared = std::make_shared<LocalShared>(size);
    std::vector<std::unique_ptr<Cluster>> ranks;
    for (int r = 0; r < size; ++r) ranks.push_back(std::make_unique<LocalCluster>(shared, r));
    return ranks;
}

}  // namespace caustica
