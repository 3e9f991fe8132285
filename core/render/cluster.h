// Several processes rendering one frame (docs/SCALING.md): the collective operations a render
// session needs from its peers, behind one seam. The MPI implementation is app/mpi_cluster.*; tests
// use make_local_cluster, threads standing in for ranks. core/ never includes MPI.
//
// Every rank runs the same render session on the same job. The sessions call the collectives
// below in the same order; a rank whose local work failed still takes part, saying so, so that
// a failure on any rank stops every rank at the next collective with that rank's message.
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustica {

/// Exit code of an interrupted render (README: exit codes).
inline constexpr int cluster_interrupted_code = 130;

/// A rank's failure, as every rank learns it.
struct RankFailure {
    int rank = 0;
    int exit_code = 1;     ///< what the process exits with: 2 scene or usage error, 1 other, 130 interrupted
    std::string message;   ///< the error's text ("scene.lua:12: gr.render: ...")
};

/// Thrown on every rank when a collective found that a rank failed.
class ClusterError : public std::runtime_error {
public:
    explicit ClusterError(RankFailure failure) : std::runtime_error(failure.message), failure_(std::move(failure)) {}
    const RankFailure& failure() const { return failure_; }
    bool interrupted() const { return failure_.exit_code == cluster_interrupted_code; }

private:
    RankFailure failure_;
};

/// The failure a caught exception means on this rank (InputError and bad_alloc: exit code 2;
/// ClusterError: its own; anything else: 1).
RankFailure failure_of(std::exception_ptr error, int rank);

class Cluster {
public:
    using Bytes = std::vector<std::uint8_t>;
    /// Renders work items [first, last) and returns their result (may throw: a failure).
    using WorkFn = std::function<Bytes(int first, int last)>;
    /// Takes the result of items [first, last) on rank 0. Never called concurrently.
    using CollectFn = std::function<void(int first, int last, const Bytes& result)>;

    virtual ~Cluster() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;

    /// Collective: each rank says whether it failed; returns the failure of the lowest failing
    /// rank (the same on every rank), or nothing when every rank is fine.
    virtual std::optional<RankFailure> agree(const std::optional<RankFailure>& mine) = 0;
    /// Collective: `bytes` of rank `root` on every rank.
    virtual void broadcast(Bytes& bytes, int root) = 0;
    /// Collective: every rank's bytes, in rank order, on every rank.
    virtual std::vector<Bytes> all_gather(const Bytes& mine) = 0;
    /// Collective: every rank's bytes, in rank order, on rank 0 (the others get nothing).
    virtual std::vector<Bytes> gather(const Bytes& mine) = 0;
    /// Collective: the element-wise sum of every rank's `values` (same length on every rank) in
    /// rank 0's; the other ranks' are left unspecified. Integer sums: exact in any order.
    virtual void reduce_sum(std::vector<std::int64_t>& values) = 0;
    /// Collective: the sum and the maximum over the ranks, on every rank.
    virtual long long all_sum(long long value) = 0;
    virtual double all_max(double value) = 0;

    /// Collective: shares work items [0, count) between the ranks in batches of `batch` handed
    /// out by rank 0 as ranks ask for them (a rank that finishes early gets more). Each rank runs
    /// `work` on the batches it gets; rank 0 `collect`s every result. A rank whose `work` throws
    /// (or whose `cancel` is set) stops working and says so; the failure of the lowest failing rank
    /// is returned on every rank once every batch is accounted for.
    virtual std::optional<RankFailure> share_work(int count, int batch, const WorkFn& work, const CollectFn& collect,
                                                  const std::atomic<bool>* cancel) = 0;

    /// Throws ClusterError on every rank when any rank failed (`mine`: this rank's error, if any;
    /// else, when `cancel` is set, this rank was interrupted). One agreement.
    void checkpoint(std::exception_ptr mine, const std::atomic<bool>* cancel = nullptr);
    /// As checkpoint, with this rank's failure (or nothing) already made.
    void checkpoint(const std::optional<RankFailure>& mine);
};

/// `size` ranks in one process, each to be driven by its own thread (tests, and a model of
/// the MPI one: same protocol, same results).
std::vector<std::unique_ptr<Cluster>> make_local_cluster(int size);

}  // namespace caustica
