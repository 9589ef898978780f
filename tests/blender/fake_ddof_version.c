/* SPDX-License-Identifier: GPL-3.0-or-later */
/* fake_ddof_version.c - a shared library that claims to be ddof 1.2.0 and has nothing else:
 * test_messages.py loads it as DDOF_LIBRARY to check the add-on's incompatible-library message. */
#if defined(__GNUC__)
#  define FAKE_API __attribute__((visibility("default")))
#else
#  define FAKE_API
#endif

FAKE_API unsigned ddof_version_number(void);
FAKE_API const char *ddof_version_string(void);

unsigned ddof_version_number(void)
{
    return 10200u;
}

const char *ddof_version_string(void)
{
    return "1.2.0";
}
