#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "child_process.hpp"

using granular::cli::ChildOutput;
using granular::cli::run_program;
using granular::cli::shell_words;

TEST_CASE("a child gets its arguments as they are: quotes and ';' in them run nothing") {
  const std::string hostile = "o'; touch PWNED-child; echo '";
  std::filesystem::remove("PWNED-child");
  // sh -c SCRIPT NAME ARG: the script compares its $1 with the text it was given.
  const auto checked = run_program({"sh", "-c", "test \"$1\" = \"o'; touch PWNED-child; echo '\"", "sh", hostile});
  CHECK(checked.started);
  CHECK(checked.status == 0);
  CHECK_FALSE(std::filesystem::exists("PWNED-child"));
}

TEST_CASE("a child's exit status, a signal's end and a program that is not there") {
  CHECK(run_program({"sh", "-c", "exit 3"}).status == 3);
  CHECK(run_program({"sh", "-c", "kill -TERM $$"}).status == 128 + 15);
  const auto missing = run_program({"granular-no-such-program"}, ChildOutput::Discard);
  CHECK_FALSE(missing.started);
  CHECK(missing.why == "No such file or directory");
}

TEST_CASE("shell_words quotes what a shell would read otherwise") {
  CHECK(shell_words({"python3", "/a/plot.py", "--out=x"}) == "python3 /a/plot.py --out=x");
  CHECK(shell_words({"--out=Bob's runs", ""}) == "'--out=Bob'\\''s runs' ''");
  CHECK(shell_words({"a;b", "$HOME"}) == "'a;b' '$HOME'");
}
