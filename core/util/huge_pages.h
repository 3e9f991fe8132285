// Large buffers backed by transparent huge pages where the kernel allows it.
#pragma once

#include <cstddef>
#include <vector>

namespace caustica {

/// Asks the kernel to back the whole 2 MiB pages inside [data, data + bytes) with transparent huge
/// pages (Linux in THP "madvise" mode; elsewhere, or where it is refused, nothing changes). A buffer
/// of a frame's size touched for the first time then faults in 2 MiB at a time rather than 4 KiB,
/// which matters where page faults are slow (docs/PERFORMANCE.md, "Progressive photon mapping").
/// Only buffers of at least huge_page_min_bytes are advised: glibc maps those on their own pages
/// (its mmap threshold rises to 32 MiB at most) and unmaps them when freed, where advice on a
/// smaller heap block would outlive it.
inline constexpr std::size_t huge_page_min_bytes = std::size_t{32} << 20;
void advise_huge_pages(void* data, std::size_t bytes);

/// v.reserve(n), the new memory advised for huge pages, when n elements are more than it holds.
/// Elements already there are kept.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
    if (n <= v.capacity()) return;
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace caustica
