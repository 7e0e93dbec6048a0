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
/// faults as well. Per index the table keeps a generation stamp, which marks what this query computed, and the
/// entry's place in a dense array that holds the entries in the order they were computed: a query touches 8 bytes
/// per index it asks for, and its entries lie together in memory that the thread's previous queries kept in cache
/// (an array indexed by node spreads them over the whole table, a few cold cache lines each). A second table of the
/// same type alive on the same thread (a query started inside another) gets storage of its own. References that
/// get() returns stay valid for the table's lifetime.
template <typename T>
class PerQueryTable
{
public:
  explicit PerQueryTable(std::size_t size)
  {
    Storage& shared = threadStorage();
    storage_ = shared.busy ? &own_ : &shared;
    storage_->busy = true;
    if (storage_->slots.size() < size) storage_->slots.resize(size);  // new slots carry stamp 0
    storage_->values.clear();
    storage_->values.reserve(size);  // no reallocation while the query holds references
    if (++storage_->generation == 0)  // wrapped: stamps of 2^32 queries ago would read as current
    {
      for (Slot& s : storage_->slots) s.stamp = 0;
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
    Slot& s = storage_->slots[i];
    if (s.stamp != storage_->generation)
    {
      s.place = std::uint32_t(storage_->values.size());
      storage_->values.push_back(make());
      s.stamp = storage_->generation;
    }
    return storage_->values[s.place];
  }

private:
  struct Slot
  {
    std::uint32_t stamp = 0;
    std::uint32_t place = 0;  ///< index into values
  };
  struct Storage
  {
    std::vector<Slot> slots;
    std::vector<T> values;
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

/// A vector a query fills, empty when made, in storage the thread's next queries reuse (as PerQueryTable's): a
/// query that makes a few dozen entries of a few hundred bytes would otherwise spend a good part of its time
/// allocating and faulting in a fresh array. A second one of the same type alive on the same thread gets storage
/// of its own.
template <typename T>
class PerQueryVector
{
public:
  PerQueryVector()
  {
    Storage& shared = threadStorage();
    storage_ = shared.busy ? &own_ : &shared;
    storage_->busy = true;
    storage_->values.clear();
  }
  ~PerQueryVector() { storage_->busy = false; }
  PerQueryVector(const PerQueryVector&) = delete;
  PerQueryVector& operator=(const PerQueryVector&) = delete;
  std::vector<T>& values() { return storage_->values; }

private:
  struct Storage
  {
    std::vector<T> values;
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
