"""The Modbus link to the card: pymodbus' synchronous TCP or RTU client, made fail-stop.

pymodbus retries a request that timed out and silently reconnects a
dropped socket.  Either would let a command reach the card twice, or let a
stream continue after commands were lost, so this wrapper uses
``retries=0`` and, on the first failure of any kind (timeout, dropped
connection, exception reply, malformed reply), closes the client and refuses
every further request until :meth:`Link.connect` is called again - which
only the back-end's operator-initiated recovery does.
"""

from __future__ import annotations

import threading

from pymodbus.client import ModbusSerialClient, ModbusTcpClient
from pymodbus.exceptions import ModbusException

from . import registers as regs


class LinkError(RuntimeError):
    """The link failed; ``exception_code`` is set when the card answered with a Modbus exception."""

    def __init__(self, message: str, exception_code: int | None = None) -> None:
        super().__init__(message)
        self.exception_code = exception_code


_EXCEPTIONS = {1: "illegal function", 2: "illegal data address", 3: "illegal data value",
               4: "device failure", 5: "acknowledge", 6: "device busy", 10: "gateway path unavailable",
               11: "gateway target failed to respond"}


class Link:
    """One Modbus client.  ``serial`` (a device or pyserial URL) selects RTU; otherwise TCP to ``host:port``."""

    def __init__(self, *, host: str, port: int, serial: str | None, baudrate: int, unit: int, timeout: float) -> None:
        self.unit = unit
        self.where = serial if serial else f"{host}:{port}"
        self.lock = threading.RLock()
        if serial:
            self.client = ModbusSerialClient(serial, baudrate=baudrate, timeout=timeout, retries=0)
        else:
            self.client = ModbusTcpClient(host, port=port, timeout=timeout, retries=0)
        self.failed: str | None = "not connected"
        self.requests = 0

    def connect(self) -> None:
        with self.lock:
            self.client.close()
            if not self.client.connect():
                self.failed = f"cannot connect to the InterpCNC at {self.where}"
                raise LinkError(self.failed)
            self.failed = None

    def close(self) -> None:
        with self.lock:
            self.client.close()
            self.failed = self.failed or "closed"

    def _fail(self, message: str, code: int | None = None) -> LinkError:
        self.failed = message
        self.client.close()        # drop any late reply with the socket
        return LinkError(message, code)

    def _call(self, what: str, fn, *args, **kwargs):
        with self.lock:
            if self.failed:
                raise LinkError(f"link to the InterpCNC at {self.where} is down ({self.failed})")
            self.requests += 1
            try:
                reply = fn(*args, device_id=self.unit, **kwargs)
            except (ModbusException, OSError) as exc:
                raise self._fail(f"{what}: no valid reply from the InterpCNC at {self.where} ({exc})") from exc
            if reply is None or reply.isError():
                code = getattr(reply, "exception_code", None)
                text = _EXCEPTIONS.get(code, "error") if code is not None else "error reply"
                raise self._fail(f"{what}: the InterpCNC answered Modbus exception {code} ({text})", code)
            return reply

    def write(self, address: int, words: list[int], what: str = "write") -> None:
        """Function 16 at ``address``."""
        self._call(what, self.client.write_registers, address, words)

    def command(self, words: list[int], what: str = "command") -> None:
        """One command at holding 2000.  Longer than 123 words: the tail first, then 2000 (whose write
        triggers the command, L490-L492)."""
        if len(words) > regs.HR_COMMAND_SIZE:
            raise LinkError(f"{what}: {len(words)} words do not fit the 150-register command buffer")
        n = regs.MAX_WRITE_REGISTERS
        if len(words) > n:
            self.write(regs.HR_COMMAND + n, words[n:], what)
        self.write(regs.HR_COMMAND, words[:n], what)

    def read_input(self, address: int, count: int, what: str = "read") -> list[int]:
        return list(self._call(what, self.client.read_input_registers, address, count=count).registers)

    def read_holding(self, address: int, count: int, what: str = "read") -> list[int]:
        return list(self._call(what, self.client.read_holding_registers, address, count=count).registers)
