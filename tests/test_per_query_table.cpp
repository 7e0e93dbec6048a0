// detail::PerQueryTable: entries computed once per table, recomputed by the next table, storage reused per thread.
#include <gtest/gtest.h>

#include <cstddef>
#include <thread>

#include "fcl_rs/traversal/per_query_table.h"

namespace {

using fcl_rs::detail::PerQueryTable;

TEST(PerQueryTable, ComputesAnEntryOnceWithinATable)
{
  PerQueryTable<int> table(8);
  int calls = 0;
  const auto make = [&](int value) { return [&calls, value] { ++calls; return value; }; };
  EXPECT_EQ(table.get(3, make(30)), 30);
  EXPECT_EQ(table.get(3, make(31)), 30);  // cached: make is not called again
  EXPECT_EQ(table.get(5, make(50)), 50);
  EXPECT_EQ(calls, 2);
}

TEST(PerQueryTable, TheNextTableRecomputesEveryEntry)
{
  for (int query = 0; query < 3; ++query)
  {
    PerQueryTable<int> table(4);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(table.get(i, [&] { return 10 * query + int(i); }), 10 * query + int(i));
  }
}

TEST(PerQueryTable, GrowsWhenALaterQueryNeedsMoreEntries)
{
  {
    PerQueryTable<int> small(2);
    EXPECT_EQ(small.get(1, [] { return 1; }), 1);
  }
  PerQueryTable<int> large(1000);
  for (std::size_t i = 0; i < 1000; ++i) EXPECT_EQ(large.get(i, [i] { return int(i) + 7; }), int(i) + 7);
}

TEST(PerQueryTable, ReferencesStayValidWhileTheTableFills)
{
  // A fresh thread: storage that no earlier query has grown.
  std::thread([] {
    PerQueryTable<int> table(1000);
    const int& first = table.get(999, [] { return 42; });
    for (std::size_t i = 0; i < 999; ++i) table.get(i, [i] { return int(i); });
    EXPECT_EQ(&table.get(999, [] { return 0; }), &first);  // entries were not moved
    EXPECT_EQ(first, 42);
  }).join();
}

TEST(PerQueryTable, ANestedTableHasItsOwnStorage)
{
  PerQueryTable<int> outer(4);
  EXPECT_EQ(outer.get(2, [] { return 20; }), 20);
  {
    PerQueryTable<int> inner(4);
    EXPECT_EQ(inner.get(2, [] { return -20; }), -20);  // not the outer query's entry
    EXPECT_EQ(inner.get(1, [] { return -10; }), -10);
  }
  EXPECT_EQ(outer.get(2, [] { return 99; }), 20);  // the inner query left the outer one's entries alone
  EXPECT_EQ(outer.get(1, [] { return 10; }), 10);
}

TEST(PerQueryTable, ThreadsDoNotShareEntries)
{
  PerQueryTable<int> here(4);
  EXPECT_EQ(here.get(0, [] { return 1; }), 1);
  int there = 0;
  std::thread([&] {
    PerQueryTable<int> table(4);
    there = table.get(0, [] { return 2; });
  }).join();
  EXPECT_EQ(there, 2);
  EXPECT_EQ(here.get(0, [] { return 3; }), 1);
}

}  // namespace
