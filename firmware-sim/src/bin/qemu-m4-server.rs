#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    use embedded_io::Write as _;
    use maglev_firmware_sim::board::cmsdk_uart::CmsdkUart;
    use maglev_firmware_sim::protocol::MAX_FRAME;
    use maglev_firmware_sim::server::Server;
    // SAFETY: the only user of UART0 in this image.
    let mut uart = unsafe { CmsdkUart::uart0_wfi() };
    let mut server = Server::new();
    let mut frame = [0u8; MAX_FRAME];
    loop {
        let b = uart.read_byte();
        if let Some(len) = server.push_byte(b, &mut frame) {
            let _ = uart.write_all(&frame[..len]);
        }
    }
}

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    maglev_firmware_sim::board::semihosting::panic(info)
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!("qemu-m4-server is a bare-metal image: build it for thumbv7em-none-eabihf");
}
