// Passwords out of shown text: libpq key=value strings, URL user info and query keys; the rest
// of the text kept as it is.
#include "base/Secrets.h"

#include <gtest/gtest.h>

namespace orbis {
namespace {

TEST(Secrets, PasswordsInConnectionStringsAndUrlsAreHidden) {
    EXPECT_EQ(redactSecrets("PG:host=db user=me password=s3cret dbname=gis"), "PG:host=db user=me password=*** dbname=gis");
    EXPECT_EQ(redactSecrets("PG:password=s3cret"), "PG:password=***");
    EXPECT_EQ(redactSecrets("host=db PASSWORD = 's3 \\'cret' port=5432"), "host=db PASSWORD = *** port=5432");
    EXPECT_EQ(redactSecrets("PG:host=db password='unterminated"), "PG:host=db password=***");
    EXPECT_EQ(redactSecrets("postgresql://me:s3cret@db:5432/gis?sslmode=require"), "postgresql://me:***@db:5432/gis?sslmode=require");
    EXPECT_EQ(redactSecrets("WFS:https://me:p@ss@host/wfs?typename=a"), "WFS:https://me:***@host/wfs?typename=a");
    EXPECT_EQ(redactSecrets("https://host/wms?user=me&password=s3cret&layers=a"), "https://host/wms?user=me&password=***&layers=a");
    // In a message, around it.
    EXPECT_EQ(redactSecrets("PG:host=db password=x: no layer 'a'"), "PG:host=db password=*** no layer 'a'");
}

TEST(Secrets, PasswordsAreTakenOutOfWhatIsSaved) {
    EXPECT_EQ(withoutPasswords("PG:host=db password=s3cret user=me"), "PG:host=db user=me");
    EXPECT_EQ(withoutPasswords("PG:host=db user=me password='a b'"), "PG:host=db user=me");
    EXPECT_EQ(withoutPasswords("PG:password=s3cret host=db"), "PG: host=db");
    EXPECT_EQ(withoutPasswords("postgresql://me:s3cret@db/gis"), "postgresql://me@db/gis");
    EXPECT_EQ(withoutPasswords("https://host/wms?password=s3cret&layers=a"), "https://host/wms?layers=a");
    EXPECT_EQ(withoutPasswords("https://host/wms?layers=a&password=s3cret"), "https://host/wms?layers=a");
    EXPECT_EQ(withoutPasswords("https://host/wms?a=1&password=s3cret&b=2"), "https://host/wms?a=1&b=2");
}

TEST(Secrets, TextWithoutPasswordsIsKept) {
    for (const char* text : {"", "/data/roads.gpkg", "PG:host=db user=me", "https://me@host/wms", "https://host/a:b@c",
                             "old_password=x", "password", "passwords=x", "http://host:8080/wfs"})
    {
        EXPECT_EQ(redactSecrets(text), text);
        EXPECT_EQ(withoutPasswords(text), text);
    }
}

TEST(Secrets, ConnectionStringsAreToldFromFiles) {
    for (const char* s : {"PG:dbname=gis", "WFS:https://host/wfs", "MSSQL:server=x", "GPKG_X:a"})
        EXPECT_TRUE(isConnectionString(s)) << s;
    for (const char* s : {"roads.gpkg", "a:b.tif", "/data/PG:x", "x/y:z.tif", "my file:x.gpkg", "/vsicurl/https://h/a.tif", ""})
        EXPECT_FALSE(isConnectionString(s)) << s;
}

}  // namespace
}  // namespace orbis
