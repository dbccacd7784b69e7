/* Which marks a terminal can show: the locale's codeset (issue 48: a
 * serial console or LC_ALL=C showed "Â±" for "±"). */
#include <langinfo.h>
#include <string.h>
#include <strings.h>

#include "uwb/reply_text.h"

enum uwbd_charset uwbd_charset_of_locale(void)
{
    const char *codeset = nl_langinfo(CODESET);
    if (codeset && (strcasecmp(codeset, "UTF-8") == 0 || strcasecmp(codeset, "utf8") == 0))
        return UWBD_CHARSET_UTF8;
    return UWBD_CHARSET_ASCII;
}
