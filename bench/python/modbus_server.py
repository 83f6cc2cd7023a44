"""Modbus RTU server for the round-trip benchmark: pymodbus holding registers on a serial port.

Usage: modbus_server.py PORT BAUD
Every holding register at address A holds A mod 65536. Prints "ready" once configured.
"""
import logging
import sys

from pymodbus import FramerType
from pymodbus.datastore import ModbusDeviceContext, ModbusSequentialDataBlock, ModbusServerContext
from pymodbus.server import StartSerialServer


def main() -> None:
    port, baud = sys.argv[1], int(sys.argv[2])
    logging.disable(logging.CRITICAL)
    # pymodbus numbers blocks from 1 and adds 1 to wire addresses: position k answers address k.
    block = ModbusSequentialDataBlock(1, [address % 65536 for address in range(8192)])
    context = ModbusServerContext(devices=ModbusDeviceContext(hr=block), single=True)
    print("ready", flush=True)
    StartSerialServer(context, framer=FramerType.RTU, port=port, baudrate=baud, parity="N", stopbits=1, bytesize=8)


if __name__ == "__main__":
    main()
