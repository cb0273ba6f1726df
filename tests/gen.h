#ifndef HPFC_TEST_GEN_H
#define HPFC_TEST_GEN_H
#endif
