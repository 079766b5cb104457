"""``OrKeyboard``: the keyboard client (std_msgs/UInt16 on /keyboard_unicode; ``smacc-key n``)."""

from __future__ import annotations

from smacc_py.clients.cl_keyboard import ClKeyboard
from smacc_py.core import Orthogonal


class OrKeyboard(Orthogonal):
    """Key presses, turned into EvKeyPress<X> by the states' CbDefaultKeyboardBehavior."""

    def on_initialize(self) -> None:
        self.create_client(ClKeyboard)
