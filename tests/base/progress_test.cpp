// base/progress.hpp: the bar and the durations the long-running commands print.
#include "base/progress.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

using namespace nesshi::base;

TEST_CASE("progress_bar fills percent of its width", "[unit][base]") {
    CHECK(progress_bar(0, 4) == "[    ]");
    CHECK(progress_bar(50, 4) == "[##  ]");
    CHECK(progress_bar(100, 4) == "[####]");
    CHECK(progress_bar(99, 40) == "[" + std::string(39, '#') + " ]");
}

TEST_CASE("format_duration: m:ss under an hour, h:mm:ss above", "[unit][base]") {
    CHECK(format_duration(0) == "0:00");
    CHECK(format_duration(65.4) == "1:05");
    CHECK(format_duration(3599.4) == "59:59");
    CHECK(format_duration(3723) == "1:02:03");
}

TEST_CASE("ProgressBar redraws in place and ends its line at the total", "[unit][base]") {
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    const ProgressBar bar(f, 10);
    bar(1, 4);
    bar(4, 4);
    std::rewind(f);
    char buf[128] = {};
    const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    CHECK(std::string(buf, n) == "\r[##        ]  25% \r[##########] 100% \n");
}
