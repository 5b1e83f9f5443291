#pragma once
// `rigel transfer`: keys of one built component (or a whole character)
// copied onto another of the same type, matched by rigId or name and side,
// controls by role and index (tools/transfer.h), over a range and with an
// offset, through app::Workspace::transfer_keys.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace rigel::cli {

struct TransferArgs {
  CLI::App* command = nullptr;  // set by add_transfer_command
  std::string scene;
  std::string from, to;
  std::string frames;
  double offset = 0.0;
  std::string output;
  bool json = false;
};

CLI::App* add_transfer_command(CLI::App& app, TransferArgs& args);
int run_transfer(const TransferArgs& args);

}  // namespace rigel::cli
