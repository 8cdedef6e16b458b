#pragma once
// The reference tables of docs/config.md and docs/elasticity.md, generated
// from the parameter tables (core/parameters.hpp). A document holds each table
// between the markers
//   <!-- generated: <id> -->  ...  <!-- end generated: <id> -->
// and `warpfem-config-reference --write <files>` rewrites the text between
// them; a test fails when the committed documents differ from the generated text.

#include <string>
#include <utility>
#include <vector>

namespace warpfem::io {

/// Every generated table: (id, markdown), e.g. ("mesh", "| key | type | ...").
std::vector<std::pair<std::string, std::string>> config_reference_tables();

/// `document` with the text between each pair of markers replaced by the table
/// of that id; throws warpfem::Error for an unknown id or an unclosed marker.
std::string update_config_reference(const std::string& document);

/// The command that regenerates the reference, for messages.
inline constexpr const char* kConfigReferenceCommand =
    "./build/io/warpfem-config-reference --write docs/config.md docs/elasticity.md";

}  // namespace warpfem::io
