#pragma once
/// What a valid match record is, checked before anything is written (matches.h).

#include <string>

#include "ricochet/db/records.h"

namespace ricochet::db {

/// Empty when the record can be written; otherwise what is wrong with it. Players are only
/// checked for their own fields and for being listed once; whether they exist is the store's.
std::string check_match(const MatchRecord& match);

}  // namespace ricochet::db
