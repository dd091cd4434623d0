/* status.c - text of the status codes, for logs and command-line tools. */
#include "grip/grip_types.h"

const char *grip_status_str(grip_status_t status)
{
    switch (status) {
    case GRIP_OK:           return "ok";
    case GRIP_WARN_CLAMPED: return "input clamped to its valid range";
    case GRIP_WARN_RATE: return "sample times disagree with the configured step rate";
    case GRIP_ERR_NULL:     return "required pointer is NULL";
    case GRIP_ERR_PARAM:    return "invalid or unsupported parameter set";
    case GRIP_ERR_INPUT:    return "non-finite or physically impossible input";
    case GRIP_ERR_STATE:    return "instance not initialised or in a failed state";
    case GRIP_ERR_DOMAIN:   return "argument outside the function's domain";
    default:                return "unknown status";
    }
}
