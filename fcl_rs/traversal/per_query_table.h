// A table indexed by node or vertex whose entries a query computes on first use, in storage reused by the thread's
// next queries.
#ifndef FCL_RS_PER_QUERY_TABLE_H
#define FCL_RS_PER_QUERY_TABLE_H

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fcl_rs {

namespace detail {

/// Entries of type T indexed 0 .. size-1, each computed by the first get() that asks for it during this table's
/// lifetime (one query). The storage belongs to the calling thread and survives the query: a fresh array per query
/// cost an allocation and a pass clearing its flags (a first-contact query visits a few dozen of a model's
/// thousands of nodes), and past malloc's mmap threshold (about a thousand nodes of moved frames) the kernel's page
/// faults as well. A generation stamp per entry marks what this query computed. A second table of the same type
/// alive on the same thread (a query started inside another) gets storage of its own.
template <typename T>
class PerQueryTable
{
public:
  explicit PerQueryTable(std::size_t size)
  {
    Storage& shared = threadStorage();
    storage_ = shared.busy ? &own_ : &shared;
    storage_->busy = true;
    if (storage_->entries.size() < size) storage_->entries.resize(size);  // new entries carry stamp 0
    if (++storage_->generation == 0)  // wrapped: stamps of 2^32 queries ago would read as current
    {
      for (Entry& e : storage_->entries) e.stamp = 0;
      storage_->generation = 1;
    }
  }
  ~PerQueryTable() { storage_->busy = false; }
  PerQueryTable(const PerQueryTable&) = delete;
  PerQueryTable& operator=(const PerQueryTable&) = delete;

  /// Entry i, computed by make() (returning T) when this query first asks for it.
  template <typename Make>
  const T& get(std::size_t i, Make&& make)
  {
    Entry& e = storage_->entries[i];
    if (e.stamp != storage_->generation)
    {
      e.value = make();
      e.stamp = storage_->generation;
    }
    return e.value;
  }

private:
  struct Entry
  {
    T value;
    std::uint32_t stamp = 0;
  };
  struct Storage
  {
    std::vector<Entry> entries;
    std::uint32_t generation = 0;
    bool busy = false;
  };
  static Storage& threadStorage()
  {
    thread_local Storage storage;
    return storage;
  }

  Storage* storage_;
  Storage own_;
};

}  // namespace detail

}  // namespace fcl_rs

#endif
