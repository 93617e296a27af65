#pragma once
/// @file block_rule_call.hpp
/// What the table build and the rule fingerprint share about calling a game's block rule
/// (RuleSet::transition): an exception it throws leaves as a RuleError naming the rule set and the
/// block key, and a rule set's name appears in messages bounded and escaped.

#include <exception>
#include <string>

#include "granular/errors.hpp"
#include "granular/extend/block.hpp"
#include "granular/rule_set.hpp"

namespace granular {

/// `key` for a message: octal, then its eight cells' material names ("0123 (cells void solid ...)").
std::string block_key_text(BlockKey key);

/// The rule set's name for a message, in single quotes: at most 40 bytes (longer names are cut,
/// with their length), every byte that is not printable ASCII as \xHH.
std::string shown_rule_set_name(const std::string& name);

/// The RuleError for `thrown`, the exception RuleSet::transition of `rules` threw on `key`:
/// "rule set 'NAME': RuleSet::transition threw on block key 0123 (cells ...): WHAT".
RuleError block_rule_error(const RuleSet& rules, BlockKey key, std::exception_ptr thrown);

}  // namespace granular
