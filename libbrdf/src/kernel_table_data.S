/* The kernel table's node file (kernel_table_file.h), written at build time by
   libbrdf_generate_kernel_table, in the library's read-only data: no process computes it. CMake
   passes the file's path as LIBBRDF_KERNEL_TABLE_FILE. GNU assembler (ELF). */
    .section .rodata
    .balign 64
    .globl libbrdf_kernel_table_data
    .hidden libbrdf_kernel_table_data
libbrdf_kernel_table_data:
    .incbin LIBBRDF_KERNEL_TABLE_FILE
    .globl libbrdf_kernel_table_data_end
    .hidden libbrdf_kernel_table_data_end
libbrdf_kernel_table_data_end:
    .section .note.GNU-stack,"",@progbits
