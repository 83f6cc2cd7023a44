"""Independent Modbus RTU peer for tests/tests/modbus_peer.rs: a pymodbus server on a port.

Usage: modbus_peer_server.py PORT [rtu|ascii]
PORT may be tcp://HOST:PORT: a TCP server with the RTU (or ASCII) framer, as a serial device
server carries the line's frames (tests/tests/tcp.rs, cli/tests/tcp.rs).
Holding registers 0-3999 (303 x 10 - 1 = 3029 holds 0, 60000; 3099 holds 42), coils 0-199.
Prints "ready" once configured.
"""
import logging
import sys

from pymodbus import FramerType
from pymodbus.datastore import ModbusDeviceContext, ModbusSequentialDataBlock, ModbusServerContext
from pymodbus.server import StartSerialServer, StartTcpServer


def main() -> None:
    logging.disable(logging.CRITICAL)
    registers = [0] * 4000
    registers[3029:3031] = [0, 60000]
    registers[3099] = 42
    # pymodbus numbers blocks from 1 and adds 1 to wire addresses: position k answers address k.
    context = ModbusServerContext(
        devices=ModbusDeviceContext(hr=ModbusSequentialDataBlock(1, registers), co=ModbusSequentialDataBlock(1, [False] * 200)),
        single=True,
    )
    print("ready", flush=True)
    # Linux pseudo-terminals refuse parity settings: 8N1.
    framer = FramerType.ASCII if len(sys.argv) > 2 and sys.argv[2] == "ascii" else FramerType.RTU
    if sys.argv[1].startswith("tcp://"):
        # A serial device server: the serial line's frames over TCP, no MBAP header.
        host, _, number = sys.argv[1][len("tcp://"):].rpartition(":")
        StartTcpServer(context, framer=framer, address=(host, int(number)))
    else:
        StartSerialServer(context, framer=framer, port=sys.argv[1], baudrate=115200, parity="N", stopbits=1, bytesize=8)


if __name__ == "__main__":
    main()
