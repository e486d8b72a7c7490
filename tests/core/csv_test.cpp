// Tests of engine/core/csv.h: a field is quoted whole and its quotes doubled.
#include "engine/core/csv.h"

#include <doctest/doctest.h>

TEST_CASE("csv: a field is quoted, its commas kept and its quotes doubled") {
  using iblx::csvQuoted;
  CHECK(csvQuoted("mis(env-cdf+ggx-vndf, balance)") == "\"mis(env-cdf+ggx-vndf, balance)\"");
  CHECK(csvQuoted("a \"b\"") == "\"a \"\"b\"\"\"");
  CHECK(csvQuoted("") == "\"\"");
}
