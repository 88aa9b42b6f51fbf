#pragma once
// Secrets out of text that is shown: connection strings and URLs name a server, and may carry a
// password that must never reach a message, a log or a saved file. No Vulkan, no GDAL.
//
//   redactSecrets("PG:host=db user=me password=s3cret")   // "PG:host=db user=me password=***"
//   redactSecrets("https://me:s3cret@host/wms?")           // "https://me:***@host/wms?"
//   withoutPasswords("PG:host=db password=s3cret user=me")  // "PG:host=db user=me"

#include <string>
#include <string_view>

namespace orbis {

/// `text` with the value of every `password=` key (libpq's key=value form: up to the next space,
/// or a single-quoted value with \' and \\ escapes; any case; also `&password=` and `?password=`
/// in a URL's query) and the password of every URL's user info (`scheme://user:password@`)
/// replaced by "***". Everything else is kept as it is. Any thread.
std::string redactSecrets(std::string_view text);

/// `text` with those passwords taken out altogether (the key and its value, or ":password" of a
/// URL's user info): what a saved file keeps of a connection string, so that the server's
/// client finds the password where it should be (PGPASSWORD, a pgpass file, a netrc). Any thread.
std::string withoutPasswords(std::string_view text);

/// Whether `source` is a driver's connection string rather than a file: a name of two or more
/// letters, digits or '_' and a colon, before any '/' ("PG:dbname=gis", "WFS:https://...").
/// Such strings are where passwords live. Any thread.
bool isConnectionString(std::string_view source);

}  // namespace orbis
