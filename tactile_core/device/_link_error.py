"""The one exception a link raises (here, below every transport, so each can import it)."""


class LinkError(Exception):
    """The link failed; the message says what happened in words a user can act on."""
